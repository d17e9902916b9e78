#!/usr/bin/python3
"""Experiment L's registered reading rule (docs/results.md section 10), applied mechanically.

Reads PREFIX_hazard.csv, PREFIX_logrank.csv, PREFIX_runs.csv and PREFIX_tests.csv in
docs/results/ (written by `experiments.sh lcsv`) and prints, for the pair `none` / `sum`:
  - the primary endpoint (first ball): log-rank p, the Cox hazard ratio of `sum` to `none`
    (the inverse of the CSV's none-to-sum row) with its 95 % CI, and the branch of the rule:
      sum faster        log-rank p < 0.05 and HR > 1 (next: an experiment that adds sum-rand)
      other direction   log-rank p < 0.05 and HR < 1
      refuted           otherwise, when the CI's upper bound is below 3 (a paper-sized effect
                        refuted for this implementation, task and KB)
      inconclusive      otherwise (reported with the CI and the registered power)
  - the secondary endpoints: best reward at the horizon (Mann-Whitney, from the tests CSV),
    runs with a best reward >= 0.5 (Fisher's exact test, SciPy, two-sided), and the log-rank
    rows of the first pickup and release.
It refuses to print anything but the run counts until both arms hold RUNS runs (40 for L),
so that an interim CSV cannot be read by accident.

Usage: /usr/bin/python3 docs/results/l_reading.py [--prefix l] [--event ball] [--runs 40]
  e.g. --prefix e2 --event pickup --runs 20 reads E2 by L's rule (HR 1.18, CI 0.61-2.27)
Written before L's reading.
"""
import argparse
import csv
import os
import sys

from scipy.stats import fisher_exact

A, B = "none", "sum"
PAPER_SIZED = 3.0
ALPHA = 0.05
SUCCESS = 0.5


def rows(path):
    if not os.path.isfile(path):
        sys.exit(f"l_reading: {path}: no such file (run experiments.sh lcsv first)")
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def pair_row(table, event=None):
    for row in table:
        if row["treatment_a"] == A and row["treatment_b"] == B and (event is None or row["event"] == event):
            return row
    sys.exit(f"l_reading: no {A} / {B} row" + (f" for event {event}" if event else ""))


def number(text):
    return float(text) if text not in ("", None) else None


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--prefix", default="l")
    parser.add_argument("--event", default="ball")
    parser.add_argument("--runs", type=int, default=40)
    args = parser.parse_args()
    here = os.path.dirname(os.path.abspath(__file__))
    path = lambda kind: os.path.join(here, f"{args.prefix}_{kind}.csv")  # noqa: E731

    runs = rows(path("runs"))
    counts = {arm: sum(r["treatment"] == arm for r in runs) for arm in (A, B)}
    print(f"runs: {A} {counts[A]}, {B} {counts[B]} (the rule reads {args.runs} an arm)")
    if min(counts.values()) < args.runs:
        print("interim: not read")
        return

    logrank = pair_row(rows(path("logrank")), args.event)
    hazard = pair_row(rows(path("hazard")), args.event)
    p = float(logrank["p"])
    hr_ab, low_ab, high_ab = (number(hazard[k]) for k in ("hazard_ratio", "ci_low", "ci_high"))
    print(f"primary, first {args.event}: events {A} {logrank['events_a']}, {B} {logrank['events_b']}; "
          f"log-rank chi2 {float(logrank['chi2']):.4g}, p {p:.4g}")
    if hr_ab is None:
        hr = low = high = None
        print(f"  hazard ratio {B} to {A}: not estimable ({hazard['note']})")
    else:
        hr, low, high = 1 / hr_ab, 1 / high_ab, 1 / low_ab
        print(f"  hazard ratio {B} to {A}: {hr:.3g} (95 % CI {low:.3g}-{high:.3g})")
    print(f"  restricted mean to {hazard['horizon']}: {A} {float(hazard['rmst_a']):.4g}, "
          f"{B} {float(hazard['rmst_b']):.4g}")

    faster = float(logrank["events_b"]) > 0 and (hr > 1 if hr is not None else float(logrank["events_a"]) == 0)
    if p < ALPHA and faster:
        branch = "sum faster: the next experiment adds sum-rand"
    elif p < ALPHA:
        branch = "an effect in the other direction"
    elif high is not None and high < PAPER_SIZED:
        branch = f"a paper-sized effect refuted (the CI's upper bound {high:.3g} < {PAPER_SIZED:g})"
    else:
        branch = "inconclusive: report the CI and the registered power"
    print(f"  rule: {branch}")

    tests = pair_row(rows(path("tests")))
    print(f"secondary, best reward at the horizon: Mann-Whitney U {float(tests['u']):g}, "
          f"p {float(tests['p']):.4g}, A12 ({A} > {B}) {float(tests['a12']):.3g}")
    wins = {arm: sum(r["treatment"] == arm and float(r["best_reward"]) >= SUCCESS for r in runs) for arm in (A, B)}
    table = [[wins[A], counts[A] - wins[A]], [wins[B], counts[B] - wins[B]]]
    print(f"secondary, runs >= {SUCCESS:g}: {A} {wins[A]} of {counts[A]}, {B} {wins[B]} of {counts[B]}; "
          f"Fisher's exact p {fisher_exact(table)[1]:.4g}")
    for event in ("pickup", "release"):
        row = pair_row(rows(path("logrank")), event)
        print(f"secondary, first {event}: events {A} {row['events_a']}, {B} {row['events_b']}; "
              f"log-rank p {float(row['p']):.4g}")


if __name__ == "__main__":
    main()
