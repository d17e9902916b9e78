#!/usr/bin/env python3
"""Statistical power of a replication design for the paper's effect.

The paper (Fig. 6, appendix): at generation 3000, 35 % of `sum` runs and 0 %
of `none` runs succeed (best-of-run reward >= 0.5), and the Mann-Whitney test
on best-of-run rewards gives p = 0.011 (20 runs each).

Two tests, both two-sided at alpha = 0.05:
  * Fisher's exact test on success counts: exact power, summing the binomial
    probabilities of every outcome (k1 of n, k0 of n) whose p-value <= alpha;
  * Mann-Whitney U on best-of-run rewards (normal approximation with the tie
    correction, as used for n >= 8 with ties): power by simulation, with a model
    of the reward clouds of Fig. 7: a successful run scores U{12..24}/24, a
    failed run 0 with probability `zero`, else U{1..11}/24.

Usage: power.py [--n 5,10,20] [--p1 0.1,0.2,0.35] [--p0 0] [--sims 4000]
Python 3 standard library only; the simulation seed is fixed.
"""
import argparse
import math
import random


def fisher_two_sided(a, n1, c, n0):
    """p-value of Fisher's exact test for a/n1 successes against c/n0."""
    total = a + c
    n = n1 + n0

    def prob(x):
        return math.comb(n1, x) * math.comb(n0, total - x) / math.comb(n, total)

    observed = prob(a)
    lo, hi = max(0, total - n0), min(n1, total)
    return min(1.0, sum(prob(x) for x in range(lo, hi + 1) if prob(x) <= observed * (1 + 1e-7)))


def binom(n, k, p):
    return math.comb(n, k) * p ** k * (1 - p) ** (n - k)


def fisher_power(n, p1, p0, alpha=0.05):
    return sum(binom(n, a, p1) * binom(n, c, p0)
               for a in range(n + 1) for c in range(n + 1)
               if binom(n, a, p1) * binom(n, c, p0) > 0 and fisher_two_sided(a, n, c, n) <= alpha)


def mann_whitney_p(x, y):
    """Two-sided p of the U test, normal approximation with tie correction."""
    n1, n2 = len(x), len(y)
    pooled = sorted((v, i) for i, v in enumerate(x + y))
    ranks = [0.0] * (n1 + n2)
    ties = 0.0
    i = 0
    while i < len(pooled):
        j = i
        while j + 1 < len(pooled) and pooled[j + 1][0] == pooled[i][0]:
            j += 1
        for k in range(i, j + 1):
            ranks[pooled[k][1]] = (i + j) / 2 + 1
        t = j - i + 1
        ties += t ** 3 - t
        i = j + 1
    u = sum(ranks[:n1]) - n1 * (n1 + 1) / 2
    n = n1 + n2
    var = n1 * n2 / 12 * ((n + 1) - ties / (n * (n - 1)))
    if var <= 0:
        return 1.0
    z = (abs(u - n1 * n2 / 2) - 0.5) / math.sqrt(var)
    return min(1.0, math.erfc(max(z, 0) / math.sqrt(2)))


def draw(rng, p_success, zero):
    if rng.random() < p_success:
        return rng.randint(12, 24) / 24
    return 0.0 if rng.random() < zero else rng.randint(1, 11) / 24


def mw_power(n, p1, p0, sims, zero1=0.6, zero0=0.85, alpha=0.05, seed=1):
    rng = random.Random(seed)
    hits = 0
    for _ in range(sims):
        x = [draw(rng, p1, zero1) for _ in range(n)]
        y = [draw(rng, p0, zero0) for _ in range(n)]
        hits += mann_whitney_p(x, y) <= alpha
    return hits / sims


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--n", default="5,10,15,20")
    ap.add_argument("--p1", default="0.1,0.2,0.35")
    ap.add_argument("--p0", type=float, default=0.0)
    ap.add_argument("--sims", type=int, default=4000)
    args = ap.parse_args()
    ns = [int(v) for v in args.n.split(",")]
    p1s = [float(v) for v in args.p1.split(",")]
    print("runs_per_treatment,p_treatment,p_control,fisher_power,mann_whitney_power")
    for n in ns:
        for p1 in p1s:
            print(f"{n},{p1},{args.p0},{fisher_power(n, p1, args.p0):.3f},"
                  f"{mw_power(n, p1, args.p0, args.sims):.3f}")


if __name__ == "__main__":
    main()
