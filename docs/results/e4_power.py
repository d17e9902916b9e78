#!/usr/bin/python3
"""Power of experiment E4 (docs/results.md section 12): `seed` against `none` on the
target task, time to first ball, 300 generations, 20 runs an arm, Holm over the
three pairs (seed-none, sum-none, seed-sum).

`none` and `sum` take E2's pooled first-ball rate (l_power.py's, 1.03e-4 a
generation: 3 % of runs by generation 300); `seed` the rate that gives the
share of seeded runs with a ball by 300 in the table. Exponential times,
right-censored at 300; the registered test is statsmodels' survdiff. Needs
Debian's python3-numpy and python3-statsmodels.

    /usr/bin/python3 docs/results/e4_power.py --csv docs/results/e4_power.csv
"""
import argparse
import csv
import math

import numpy as np

from l_power import draw, e2_ball_rate
from prereg_power import holm_first, logrank_p


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--csv")
    parser.add_argument("--trials", type=int, default=2000)
    args = parser.parse_args()
    events, exposure = e2_ball_rate()
    base = events / exposure
    horizon, n = 300, 20
    rows = []
    for p_seed in (0.1, 0.2, 0.3, 0.5, 0.7):
        rate_seed = -math.log(1 - p_seed) / horizon
        rng = np.random.default_rng(int(p_seed * 100))
        hits = 0
        for _ in range(args.trials):
            none, summed, seed = draw(rng, base, n, horizon), draw(rng, base, n, horizon), draw(rng, rate_seed, n, horizon)
            ps = [logrank_p(seed, none), logrank_p(summed, none), logrank_p(seed, summed)]
            hits += holm_first(ps) < 0.05
        row = {"runs_per_arm": n, "p_none_by_300": round(1 - math.exp(-base * horizon), 3),
               "p_seed_by_300": p_seed, "hazard_ratio": round(rate_seed / base, 1), "power": round(hits / args.trials, 3)}
        rows.append(row)
        print(row)
    if args.csv:
        with open(args.csv, "w", newline="") as f:
            writer = csv.DictWriter(f, fieldnames=list(rows[0]))
            writer.writeheader()
            writer.writerows(rows)


if __name__ == "__main__":
    main()
