#!/usr/bin/python3
"""E4's secondary endpoint (docs/results.md section 12): runs whose best reward at generation
300 is >= 0.5, per arm, and Fisher's exact test (SciPy, two-sided) for every pair of arms,
Holm-adjusted over the three pairs. Reads docs/results/e4_runs.csv (one row a run, written by
`stepstone stats --runs-csv`), prints a CSV on stdout:
    treatment_a,treatment_b,runs_a,runs_b,successes_a,successes_b,p,p_holm
Usage: /usr/bin/python3 docs/results/e4_fisher.py [e4_runs.csv] > e4_fisher.csv
Written before E4's reading; it takes the arms in the order the CSV first names them."""
import csv
import itertools
import os
import sys

from scipy.stats import fisher_exact

THRESHOLD = 0.5


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    path = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "e4_runs.csv")
    runs, successes, order = {}, {}, []
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            arm = row["treatment"]
            if arm not in runs:
                order.append(arm)
                runs[arm] = successes[arm] = 0
            runs[arm] += 1
            successes[arm] += float(row["best_reward"]) >= THRESHOLD
    pairs = list(itertools.combinations(order, 2))
    rows = []
    for a, b in pairs:
        table = [[successes[a], runs[a] - successes[a]], [successes[b], runs[b] - successes[b]]]
        rows.append([a, b, runs[a], runs[b], successes[a], successes[b], fisher_exact(table)[1]])
    # Holm: the k-th smallest p times (m - k), running maximum, capped at 1
    ranked = sorted(range(len(rows)), key=lambda i: rows[i][-1])
    running = 0.0
    for k, i in enumerate(ranked):
        running = max(running, min(1.0, (len(rows) - k) * rows[i][-1]))
        rows[i].append(running)
    out = csv.writer(sys.stdout, lineterminator="\n")
    out.writerow(["treatment_a", "treatment_b", "runs_a", "runs_b", "successes_a", "successes_b", "p", "p_holm"])
    for r in rows:
        out.writerow(r[:6] + [f"{r[6]:.6g}", f"{r[7]:.6g}"])


if __name__ == "__main__":
    main()
