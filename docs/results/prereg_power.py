#!/usr/bin/python3
"""Power of the pre-registered experiments E1 and E2 (docs/results.md section 9).

Each simulated experiment draws, for 3 arms of N runs, a first-event generation
per run from an exponential time to event whose rate gives the arm's chance of
an event within the horizon (right-censored at the horizon), and applies the
registered test: the log-rank test of `sum` against `none` with Holm's
correction over the 3 pairs. Power is the share of experiments where that
adjusted p is below 0.05. Needs Debian's python3-numpy and python3-statsmodels.

    /usr/bin/python3 docs/results/prereg_power.py --csv docs/results/prereg_power.csv
"""
import argparse
import csv
import math

import numpy as np
from statsmodels.duration.survfunc import survdiff


def holm_first(ps):
    """Holm-adjusted p of the first of the given p values."""
    order = sorted(range(len(ps)), key=lambda i: ps[i])
    adjusted, running = [0.0] * len(ps), 0.0
    for rank, i in enumerate(order):
        running = max(running, min(1.0, (len(ps) - rank) * ps[i]))
        adjusted[i] = running
    return adjusted[0]


def draw(rng, p_event, n, horizon):
    if p_event <= 0:
        return np.full(n, float(horizon)), np.zeros(n, int)
    rate = -math.log(1.0 - min(p_event, 0.999999)) / horizon
    t = np.ceil(rng.exponential(1.0 / rate, n))
    observed = (t <= horizon).astype(int)
    return np.minimum(t, horizon), observed


def logrank_p(a, b):
    times = np.concatenate([a[0], b[0]])
    status = np.concatenate([a[1], b[1]])
    groups = np.array([0] * len(a[0]) + [1] * len(b[0]))
    if status.sum() == 0:
        return 1.0
    return float(survdiff(times, status, groups)[1])


def power(p_none, p_sum, p_rand, n, horizon, trials, seed):
    rng = np.random.default_rng(seed)
    hits = 0
    for _ in range(trials):
        none, summed, rand = (draw(rng, p, n, horizon) for p in (p_none, p_sum, p_rand))
        ps = [logrank_p(summed, none), logrank_p(summed, rand), logrank_p(rand, none)]
        hits += holm_first(ps) < 0.05
    return hits / trials


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--csv", help="write the table here")
    parser.add_argument("--trials", type=int, default=1000)
    parser.add_argument("--runs", type=int, help="one design only: runs per arm (with --p-control, --p-sum)")
    parser.add_argument("--p-control", type=float, help="chance of the event by generation 500 without shaping")
    parser.add_argument("--p-sum", type=float, help="chance of the event by generation 500 under sum")
    args = parser.parse_args()
    if args.runs:
        if args.p_control is None or args.p_sum is None:
            parser.error("--runs needs --p-control and --p-sum")
        pw = power(args.p_control, args.p_sum, args.p_control, args.runs, 500, args.trials, seed=args.runs)
        print(f"n={args.runs} p_control={args.p_control} p_sum={args.p_sum} power={pw:.3f}")
        return
    rows = []
    horizon = 500
    # chance of a first event by the horizon, per arm: control (none and sum-rand alike), shaped
    for n in (20, 30):
        for p_control in (0.1, 0.2, 0.3, 0.4):
            for p_sum in (0.4, 0.5, 0.6, 0.8):
                if p_sum <= p_control:
                    continue
                hr = (math.log(1 - min(p_sum, 0.999999)) / math.log(1 - p_control))
                pw = power(p_control, p_sum, p_control, n, horizon, args.trials, seed=n * 1000 + int(p_sum * 100))
                rows.append({"runs_per_arm": n, "p_control": p_control, "p_sum": p_sum,
                             "hazard_ratio": round(hr, 2), "power": round(pw, 3)})
                print(f"n={n} p_control={p_control} p_sum={p_sum} HR={hr:.2f} power={pw:.3f}")
    if args.csv:
        with open(args.csv, "w", newline="") as f:
            writer = csv.DictWriter(f, fieldnames=list(rows[0]))
            writer.writeheader()
            writer.writerows(rows)


if __name__ == "__main__":
    main()
