#!/usr/bin/env python3
"""Reference values for tests/stats (not run by ctest).

Pure Python, standard library only, and independent of lib/stats:
  * U by comparing every pair of values;
  * exact p-values by enumerating every assignment of the pooled ranks with
    itertools.combinations, or, where that is too many, from the exact integer
    coefficients of the Gaussian binomial [n_a + n_b choose n_a]_q (whose
    coefficient of q^u counts the assignments with U = u), computed with Python
    integers and exact polynomial division;
  * the normal approximation from mid-ranks with math.erfc;
  * Holm and type-7 quantiles straight from their definitions.
If SciPy and NumPy are importable, every value is also compared with
scipy.stats.mannwhitneyu(x, y, alternative="two-sided", method="auto"),
and numpy.percentile; a mismatch stops the script.

Run: python3 tests/stats/oracle.py
"""

import itertools
import math
from fractions import Fraction

try:
    import numpy
    import scipy
    import scipy.stats
except ImportError:  # the pure-Python values stand alone
    scipy = None

ENUMERATION_LIMIT = 4_000_000  # assignments enumerated one by one at most


# --- Mann-Whitney -------------------------------------------------------------

def u_statistic(a, b):
    """U of a: #(x > y) + 0.5 #(x == y) over all pairs."""
    return sum(1.0 if x > y else 0.5 if x == y else 0.0 for x in a for y in b)


def has_ties(values):
    return len(set(values)) != len(values)


def counts_by_enumeration(n_a, n_b):
    """counts[u] = number of n_a-subsets of the ranks 0..N-1 whose U is u."""
    counts = [0] * (n_a * n_b + 1)
    offset = n_a * (n_a - 1) // 2
    for chosen in itertools.combinations(range(n_a + n_b), n_a):
        counts[sum(chosen) - offset] += 1
    return counts


def poly_mul(p, q):
    out = [0] * (len(p) + len(q) - 1)
    for i, x in enumerate(p):
        if x:
            for j, y in enumerate(q):
                out[i + j] += x * y
    return out


def poly_div_exact(p, d):
    """p / d for integer polynomials where d divides p and d[0] == 1."""
    p = list(p)
    out = [0] * (len(p) - len(d) + 1)
    for i in range(len(out)):
        c = p[i]
        out[i] = c
        if c:
            for j, y in enumerate(d):
                p[i + j] -= c * y
    assert all(x == 0 for x in p), "inexact division"
    return out


def counts_by_gaussian_binomial(n_a, n_b):
    """Coefficients of prod_{i=1..n_a} (1 - q^(n_b + i)) / (1 - q^i)."""
    counts = [1]
    for i in range(1, n_a + 1):
        counts = poly_mul(counts, [1] + [0] * (n_b + i - 1) + [-1])
        counts = poly_div_exact(counts, [1] + [0] * (i - 1) + [-1])
    counts = counts[: n_a * n_b + 1]
    assert sum(counts) == math.comb(n_a + n_b, n_a)
    return counts


def null_counts(n_a, n_b):
    if math.comb(n_a + n_b, n_a) <= ENUMERATION_LIMIT:
        return counts_by_enumeration(n_a, n_b), "enumeration"
    return counts_by_gaussian_binomial(n_a, n_b), "gaussian binomial"


def exact_cdf(n_a, n_b, k):
    """P(U <= k) under H0 without ties, as an exact fraction."""
    counts, how = null_counts(n_a, n_b)
    return Fraction(sum(counts[: k + 1]), math.comb(n_a + n_b, n_a)), how


def mid_ranks(values):
    order = sorted(range(len(values)), key=lambda i: values[i])
    ranks = [0.0] * len(values)
    i = 0
    while i < len(order):
        j = i
        while j + 1 < len(order) and values[order[j + 1]] == values[order[i]]:
            j += 1
        for k in range(i, j + 1):
            ranks[order[k]] = (i + j) / 2 + 1  # 1-based mean rank
        i = j + 1
    return ranks


def mann_whitney(a, b):
    """(U_a, p, method, how) with SciPy's method="auto" rule."""
    n_a, n_b = len(a), len(b)
    u_a = u_statistic(a, b)
    # the same U from the rank sum, as a check of u_statistic
    ranks = mid_ranks(a + b)
    assert abs(sum(ranks[:n_a]) - n_a * (n_a + 1) / 2 - u_a) < 1e-9
    u = max(u_a, n_a * n_b - u_a)
    if min(n_a, n_b) <= 8 and not has_ties(a + b):
        cdf, how = exact_cdf(n_a, n_b, int(n_a * n_b - u))
        return u_a, float(min(Fraction(1), 2 * cdf)), "exact", how
    n = n_a + n_b
    groups = {}
    for x in a + b:
        groups[x] = groups.get(x, 0) + 1
    tie_term = sum(t**3 - t for t in groups.values())
    variance = n_a * n_b / 12 * ((n + 1) - tie_term / (n * (n - 1)))
    numerator = u - n_a * n_b / 2 - 0.5
    if variance <= 0 or numerator <= 0:
        return u_a, 1.0, "asymptotic", "normal"
    z = numerator / math.sqrt(variance)
    return u_a, min(1.0, math.erfc(z / math.sqrt(2))), "asymptotic", "normal"


# --- Holm, quantiles ----------------------------------------------------------

def holm(p):
    m = len(p)
    order = sorted(range(m), key=lambda i: p[i])
    out = [0.0] * m
    for rank, i in enumerate(order):
        out[i] = min(1.0, max((m - j) * p[order[j]] for j in range(rank + 1)))
    return out


def quantile7(values, q):
    x = sorted(values)
    h = (len(x) - 1) * q
    lo = math.floor(h)
    hi = min(lo + 1, len(x) - 1)
    return x[lo] + (h - lo) * (x[hi] - x[lo])


# --- data (the same literals are in tests/stats/*_test.cpp) --------------------

SAMPLES = {
    # Shier (2004), "Statistics: 2.3 The Mann-Whitney U Test": ages at diagnosis
    "shier_males_females": ([19, 22, 16, 29, 24], [20, 11, 17, 12]),
    # Hollander & Wolfe (1973), p. 69, the two-sample example of R's ?wilcox.test
    "hollander_wolfe": ([0.80, 0.83, 1.89, 1.04, 1.45, 1.38, 1.91, 1.64, 0.73, 1.46],
                        [1.15, 0.88, 0.90, 0.74, 1.21]),
    "two_vs_three": ([1, 2], [3, 4, 5]),
    "small_ties": ([1, 2, 2], [2, 3]),
    "twenty_no_ties": (
        [0.628, 0.48, 0.73, 0.288, 0.587, 0.596, 0.457, 0.516, 0.625, 0.296,
         0.614, 0.717, 0.439, 0.808, 0.633, 0.578, 0.543, 0.706, 0.645, 0.454],
        [0.537, 0.227, 0.574, 0.23, 0.148, 0.327, 0.643, 0.55, 0.34, 0.487,
         0.37, 0.646, 0.231, 0.305, 0.255, 0.165, 0.615, 0.666, 0.542, 0.329]),
    # rewards k/24 with many zeros
    "twenty_rewards": (
        [k / 24 for k in [8, 0, 6, 0, 2, 8, 0, 0, 0, 8, 3, 0, 12, 1, 2, 8, 2, 4, 0, 0]],
        [k / 24 for k in [2, 2, 2, 2, 0, 0, 0, 0, 8, 0, 8, 0, 2, 8, 0, 3, 0, 0, 3, 0]]),
    "eight_vs_twenty": (
        [0.147, 0.543, 0.027, 0.528, 0.979, 0.863, 0.696, 0.261],
        [0.567, 0.367, 0.972, 0.733, 0.981, 0.53, 0.423, 1.012, 1.185, 1.053,
         1.006, 1.018, 0.94, 0.427, 0.718, 0.556, 0.229, 0.228, 0.479, 0.459]),
    # the 8 | 9 boundary of method="auto"
    "eight_vs_nine": ([1.5, 2.5, 3.5, 4.5, 5.5, 6.5, 7.5, 8.5],
                      [3, 5, 7, 9, 10, 11, 12, 13, 14]),
    "nine_vs_nine": ([1.5, 2.5, 3.5, 4.5, 5.5, 6.5, 7.5, 8.5, 9.5],
                     [3, 5, 7, 9, 10, 11, 12, 13, 14]),
}

EXACT_CDF_POINTS = [(8, 8, 13), (8, 8, 14), (10, 10, 23), (10, 10, 24),
                    (20, 20, 127), (20, 20, 128), (50, 50, 0), (50, 50, 900),
                    (50, 50, 1100), (50, 50, 1249), (3, 40, 20)]

HOLM_INPUTS = [[0.01, 0.04, 0.03, 0.005], [0.2, 0.01, 0.2, 0.5, 0.04], [0.6, 0.7]]

QUANTILE_INPUTS = [[1, 2, 3, 4], [7], [3, 1, 2], [0, 0, 0, 1, 5, 5, 9, 10, 2.5, 4]]


def main():
    print("# Mann-Whitney U, two-sided, method='auto'")
    for name, (a, b) in SAMPLES.items():
        a, b = [float(x) for x in a], [float(x) for x in b]
        u, p, method, how = mann_whitney(a, b)
        u_swapped, p_swapped, _, _ = mann_whitney(b, a)
        assert u_swapped == len(a) * len(b) - u and p_swapped == p
        line = f"{name}: U = {u!r}, p = {p!r} ({method}, {how})"
        if scipy is not None:
            res = scipy.stats.mannwhitneyu(a, b, alternative="two-sided", method="auto")
            assert res.statistic == u, (name, res.statistic, u)
            assert math.isclose(res.pvalue, p, rel_tol=1e-12), (name, res.pvalue, p)
            line += f"; scipy {scipy.__version__}: U = {res.statistic!r}, p = {res.pvalue!r}"
        print(line)

    print("\n# P(U <= k) under H0, no ties")
    for n_a, n_b, k in EXACT_CDF_POINTS:
        cdf, how = exact_cdf(n_a, n_b, k)
        print(f"n_a = {n_a}, n_b = {n_b}, k = {k}: {float(cdf)!r} = {cdf} ({how})")

    print("\n# Holm")
    for p in HOLM_INPUTS:
        print(f"{p} -> {holm(p)!r}")

    print("\n# type-7 quartiles")
    for v in QUANTILE_INPUTS:
        q = [quantile7(v, x) for x in (0.25, 0.5, 0.75)]
        line = f"{v}: q1, median, q3 = {q!r}, mean = {sum(v) / len(v)!r}"
        if scipy is not None:
            ref = [float(numpy.percentile(v, 100 * x)) for x in (0.25, 0.5, 0.75)]
            assert all(math.isclose(r, s, rel_tol=1e-14) for r, s in zip(ref, q)), (v, ref, q)
            line += f"; numpy {numpy.__version__} percentile agrees"
        print(line)


if __name__ == "__main__":
    main()
