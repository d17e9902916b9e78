#!/usr/bin/env python3
"""E1 diagnostic: does the same-task KB rank ball-collecting policies above the others?

For every `sum` and `sum-rand` run of E1, over all evaluated policies: the mean r_max of the
policies that collected a ball and of those that did not, and the Vargha-Delaney A12 of the
two (P(r_max of a collector > r_max of a non-collector) + ties / 2, from the rank sums;
SciPy's mannwhitneyu gives U); among the policies that collected no ball, the Spearman
correlation of r_max with the steps they carried a ball (does the signal grade the precursor
of a score?). Also the share of policies whose r_max is the KB's largest
average (saturated). Writes docs/results/e1_signal.csv.

Usage: /usr/bin/python3 docs/results/e1_signal.py E1_CAMPAIGN_DIR
"""
import csv
import glob
import os
import sqlite3
import sys

import numpy as np
from scipy.stats import mannwhitneyu, spearmanr


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    camp = sys.argv[1]
    out = os.path.join(os.path.dirname(os.path.abspath(__file__)), "e1_signal.csv")
    rows = []
    for treatment in ("sum", "sum-rand"):
        for path in sorted(glob.glob(os.path.join(camp, "target", treatment, "seed-*.db"))):
            db = sqlite3.connect(f"file:{path}?mode=ro", uri=True)
            data = np.array(db.execute("SELECT shaping, balls > 0, carry_steps FROM individual"
                                       " WHERE shaping IS NOT NULL").fetchall(), dtype=float)
            r, hit, carry = data[:, 0], data[:, 1] > 0, data[:, 2]
            row = {"treatment": treatment, "seed": int(os.path.basename(path)[5:-3]),
                   "policies": len(r), "collectors": int(hit.sum()),
                   "mean_r_max_collectors": float(r[hit].mean()) if hit.any() else "",
                   "mean_r_max_others": float(r[~hit].mean()),
                   "a12": "", "share_r_max_at_top": float((r >= r.max()).mean()),
                   "rho_r_max_carry_others": float(spearmanr(r[~hit], carry[~hit]).correlation)}
            if hit.any():
                u = mannwhitneyu(r[hit], r[~hit], alternative="two-sided").statistic
                row["a12"] = float(u / (hit.sum() * (~hit).sum()))
            rows.append(row)
    with open(out, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    for t in ("sum", "sum-rand"):
        sel = [x for x in rows if x["treatment"] == t and x["collectors"] > 0]
        print(t, "runs with collectors", len(sel), "A12 per run", [round(x["a12"], 3) for x in sel],
              "mean r_max collectors", [round(x["mean_r_max_collectors"], 3) for x in sel],
              "others", [round(x["mean_r_max_others"], 3) for x in sel])
        every = [x["rho_r_max_carry_others"] for x in rows if x["treatment"] == t]
        print(t, "Spearman r_max ~ carry steps among non-collectors: median", round(float(np.median(every)), 3),
              "range", round(min(every), 3), round(max(every), 3))


if __name__ == "__main__":
    main()
