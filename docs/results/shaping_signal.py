#!/usr/bin/env python3
"""The shaping signal of target runs: r_max (individual.r_max; individual.shaping in files
of schema 7 and older) and task
reward of the evaluated policies, per treatment, over generation windows.

Usage:
  shaping_signal.py CAMPAIGN_DIR [--window 100] [--seeds 1,2] [--csv OUT.csv]
  shaping_signal.py --runs RUN.db [RUN.db ...]      (one row per file, all generations)

For each (treatment, window): policies, mean r_max, share with r_max > 0,
r_max quartiles, mean reward and share with reward > 0, pooled over seeds.
Python 3 standard library only; files are opened read-only.
"""
import argparse
import csv
import glob
import os
import sqlite3
import sys


def quartiles(values):
    if not values:
        return (float("nan"),) * 3
    v = sorted(values)

    def q(p):  # type 7
        h = (len(v) - 1) * p
        lo = int(h)
        return v[lo] + (h - lo) * (v[min(lo + 1, len(v) - 1)] - v[lo])
    return q(0.25), q(0.5), q(0.75)


def rows_of(path, window):
    con = sqlite3.connect(f"file:{path}?mode=ro", uri=True)
    out = {}
    columns = {row[1] for row in con.execute("PRAGMA table_info(individual)")}
    score = "r_max" if "r_max" in columns else "shaping"
    for gen, shaping, reward in con.execute(f"SELECT generation, {score}, reward FROM individual"):
        key = gen // window * window if window else 0
        out.setdefault(key, []).append((shaping, reward))
    return out


def summarise(label, key, pairs):
    shaped = [s for s, _ in pairs if s is not None]
    rewards = [r for _, r in pairs]
    q1, med, q3 = quartiles(shaped)
    n = len(pairs)
    return {
        "set": label, "generations_from": key, "policies": n,
        "mean_r_max": sum(shaped) / len(shaped) if shaped else "",
        "share_r_max_pos": sum(s > 0 for s in shaped) / len(shaped) if shaped else "",
        "r_max_q1": q1 if shaped else "", "r_max_median": med if shaped else "", "r_max_q3": q3 if shaped else "",
        "mean_reward": sum(rewards) / n, "share_reward_pos": sum(r > 0 for r in rewards) / n,
    }


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("campaign", nargs="?")
    ap.add_argument("--runs", nargs="+")
    ap.add_argument("--window", type=int, default=100)
    ap.add_argument("--csv")
    ap.add_argument("--seeds", help="comma-separated seeds to include (default: every run file)")
    args = ap.parse_args()
    table = []
    if args.runs:
        for path in args.runs:
            pooled = [p for ps in rows_of(path, 0).values() for p in ps]
            table.append(summarise(os.path.basename(path), 0, pooled))
    elif args.campaign:
        for tdir in sorted(glob.glob(os.path.join(args.campaign, "target", "*"))):
            pooled = {}
            paths = sorted(glob.glob(os.path.join(tdir, "seed-*.db")))
            if args.seeds:
                wanted = {f"seed-{v.strip()}.db" for v in args.seeds.split(",")}
                paths = [p for p in paths if os.path.basename(p) in wanted]
            for path in paths:
                for key, pairs in rows_of(path, args.window).items():
                    pooled.setdefault(key, []).extend(pairs)
            for key in sorted(pooled):
                table.append(summarise(os.path.basename(tdir), key, pooled[key]))
    else:
        sys.exit("give a campaign directory or --runs FILE...")
    fields = list(table[0].keys()) if table else []
    out = open(args.csv, "w", newline="") if args.csv else sys.stdout
    w = csv.DictWriter(out, fieldnames=fields, lineterminator="\n")
    w.writeheader()
    for row in table:
        w.writerow({k: (f"{v:.4g}" if isinstance(v, float) else v) for k, v in row.items()})


if __name__ == "__main__":
    main()
