#!/usr/bin/env python3
"""Does a KB give the target task's ball-collecting policies a higher r_max
than the policies a search otherwise finds? For the stored genomes of the
given target runs from a generation on, computes r_max under each KB file
(`stepstone shape`) and compares the policies that scored a ball with those
that did not: the mean r_max of each group and the probability that a random
collector's r_max exceeds a random non-collector's (A12, ties count half).

Usage: signal_vs_balls.py --runs RUN.db [RUN.db ...] --kb NAME=KB.db [--kb ...]
                          [--from-generation 470] [--stepstone PATH] [--csv OUT.csv]
Python 3 standard library.
"""
import argparse
import csv
import json
import os
import sqlite3
import subprocess
import sys


def stored_policies(run, first):
    with sqlite3.connect(f"file:{run}?mode=ro", uri=True) as db:
        return db.execute(
            "SELECT i.id, i.generation, i.reward, i.balls FROM genome g "
            "JOIN individual i ON i.run_id = g.run_id AND i.id = g.individual_id "
            "WHERE i.generation >= ? ORDER BY i.id", (first,)).fetchall()


def r_max(stepstone, kb, run, individual):
    out = subprocess.run([stepstone, "shape", "--kb", kb, "--run", run, "--individual", str(individual), "--json"],
                         check=True, capture_output=True, text=True).stdout
    return json.loads(out)["r_max"]


def a12(xs, ys):
    if not xs or not ys:
        return float("nan")
    wins = sum((x > y) + 0.5 * (x == y) for x in xs for y in ys)
    return wins / (len(xs) * len(ys))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--runs", nargs="+", required=True)
    ap.add_argument("--kb", action="append", required=True, help="NAME=KB.db")
    ap.add_argument("--from-generation", type=int, default=470)
    ap.add_argument("--stepstone", default="stepstone")
    ap.add_argument("--csv")
    args = ap.parse_args()
    kbs = [kb.split("=", 1) for kb in args.kb]

    rows = []
    for run in args.runs:
        policies = stored_policies(run, args.from_generation)
        print(f"{run}: {len(policies)} stored policies", file=sys.stderr)
        for individual, generation, reward, balls in policies:
            row = {"run": os.path.relpath(run), "individual": individual, "generation": generation,
                   "reward": reward, "balls": balls}
            for name, kb in kbs:
                row[f"r_max_{name}"] = r_max(args.stepstone, kb, run, individual)
            rows.append(row)

    if args.csv:
        with open(args.csv, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(rows[0]))
            w.writeheader()
            w.writerows(rows)
    print("kb,collectors,mean_r_max_collectors,others,mean_r_max_others,a12_collectors_over_others")
    for name, _ in kbs:
        xs = [r[f"r_max_{name}"] for r in rows if r["balls"] > 0]
        ys = [r[f"r_max_{name}"] for r in rows if r["balls"] == 0]
        mean = lambda v: sum(v) / len(v) if v else float("nan")
        print(f"{name},{len(xs)},{mean(xs):.4f},{len(ys)},{mean(ys):.4f},{a12(xs, ys):.3f}")


if __name__ == "__main__":
    main()
