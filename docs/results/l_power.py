#!/usr/bin/python3
"""Power of experiment L (docs/results.md section 10): `none` against `sum` on the
target task, time to first ball, 2000 generations.

The unshaped hazard is E2's pooled first-ball rate: the ball events of every arm
of docs/results/e2_events.csv over their generations at risk (E2 found no
difference between its arms, so the three are pooled). Each simulated
experiment draws, for two arms of N runs, a first-ball generation per run from
an exponential time to event (the control at that rate, `sum` at HR times it),
right-censored at 2000, and applies the registered test: one two-sided log-rank
test at 0.05 (statsmodels' survdiff). Power is the share of experiments where
p < 0.05. Needs Debian's python3-numpy and python3-statsmodels.

    /usr/bin/python3 docs/results/l_power.py --csv docs/results/l_power.csv
"""
import argparse
import csv
import math
import os

import numpy as np
from statsmodels.duration.survfunc import survdiff

HERE = os.path.dirname(os.path.abspath(__file__))


def e2_ball_rate():
    """First-ball events per generation at risk, pooled over E2's arms."""
    events, exposure = 0, 0.0
    with open(os.path.join(HERE, "e2_events.csv"), newline="") as f:
        for row in csv.DictReader(f):
            if row["event"] != "ball":
                continue
            events += int(row["observed"])
            exposure += float(row["generation"])
    return events, exposure


def draw(rng, rate, n, horizon):
    t = np.ceil(rng.exponential(1.0 / rate, n))
    return np.minimum(t, horizon), (t <= horizon).astype(int)


def power(rate, hr, n, horizon, trials, seed):
    rng = np.random.default_rng(seed)
    hits = 0
    for _ in range(trials):
        none, summed = draw(rng, rate, n, horizon), draw(rng, rate * hr, n, horizon)
        times = np.concatenate([none[0], summed[0]])
        status = np.concatenate([none[1], summed[1]])
        if status.sum() == 0 or status.sum() == len(status):
            continue
        groups = np.array([0] * n + [1] * n)
        hits += survdiff(times, status, groups)[1] < 0.05
    return hits / trials


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--csv", help="write the table here")
    parser.add_argument("--trials", type=int, default=2000)
    args = parser.parse_args()
    events, exposure = e2_ball_rate()
    rate = events / exposure
    horizon = 2000
    print(f"E2 pooled first-ball rate: {events} events / {exposure:.0f} generations at risk = {rate:.3g} a generation")
    rows = []
    for n in (40, 30, 20):
        for hr in (2.0, 3.0, 4.0, 6.0):
            pw = power(rate, hr, n, horizon, args.trials, seed=n * 100 + int(hr * 10))
            p_none = 1 - math.exp(-rate * horizon)
            p_sum = 1 - math.exp(-rate * hr * horizon)
            rows.append({"runs_per_arm": n, "hazard_ratio": hr, "p_none_by_2000": round(p_none, 3),
                         "p_sum_by_2000": round(p_sum, 3), "power": round(pw, 3)})
            print(f"n={n} HR={hr} P(ball by 2000) none {p_none:.2f} sum {p_sum:.2f} power={pw:.3f}")
    if args.csv:
        with open(args.csv, "w", newline="") as f:
            writer = csv.DictWriter(f, fieldnames=list(rows[0]))
            writer.writeheader()
            writer.writerows(rows)


if __name__ == "__main__":
    main()
