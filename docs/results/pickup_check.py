#!/usr/bin/env python3
"""Progress short of a ball on the target task: for each target run of a
campaign, replays its most recent stored genomes and counts those that carry a
ball at some step (switch pressed, ball reached and picked up).

Usage: pickup_check.py CAMPAIGN_DIR [--stepstone PATH] [--last 30] [--from-generation 450]
                       [--seeds 1,2] [--csv OUT.csv]
Python 3 standard library; runs `stepstone replay --csv` on each genome.
"""
import argparse
import csv
import glob
import os
import sqlite3
import subprocess
import sys
import tempfile


def carries(stepstone, run, individual, tmp):
    out = os.path.join(tmp, "steps.csv")
    subprocess.run([stepstone, "replay", run, "--individual", str(individual), "--csv", out, "--force"],
                   check=True, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    with open(out, newline="") as f:
        return any(float(row["carrying"]) > 0 for row in csv.DictReader(f))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("campaign")
    ap.add_argument("--stepstone", default="stepstone")
    ap.add_argument("--last", type=int, default=30)
    ap.add_argument("--from-generation", type=int, default=450)
    ap.add_argument("--seeds")
    ap.add_argument("--csv")
    args = ap.parse_args()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for run in sorted(glob.glob(os.path.join(args.campaign, "target", "*", "seed-*.db"))):
            seed = os.path.basename(run)[5:-3]
            if args.seeds and seed not in args.seeds.split(","):
                continue
            con = sqlite3.connect(f"file:{run}?mode=ro", uri=True)
            ids = [r[0] for r in con.execute(
                "SELECT i.id FROM individual i JOIN genome g ON g.individual_id = i.id "
                "WHERE i.generation >= ? ORDER BY i.id DESC LIMIT ?", (args.from_generation, args.last))]
            n = sum(carries(args.stepstone, run, i, tmp) for i in ids)
            rows.append({"treatment": os.path.basename(os.path.dirname(run)), "seed": seed,
                         "policies": len(ids), "carrying": n})
    out = open(args.csv, "w", newline="") if args.csv else sys.stdout
    w = csv.DictWriter(out, fieldnames=["treatment", "seed", "policies", "carrying"], lineterminator="\n")
    w.writeheader()
    w.writerows(rows)


if __name__ == "__main__":
    main()
