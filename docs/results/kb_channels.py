#!/usr/bin/python3
"""Which channels make a run's KB segments new: for each segment a run's KB
inserted at generation G, its nearest segment among those inserted before G,
and the share of the squared distance that each channel group carries.

Usage: kb_channels.py RUN.db GENERATION [SAMPLE]   (needs numpy)
"""
import sqlite3
import sys

import numpy as np

from segments import decode

GROUPS = {"lasers (0-2)": [0, 1, 2], "ball/basket/switch lights (3-8)": [3, 4, 5, 6, 7, 8],
          "bumpers (9-10)": [9, 10], "carrying (11)": [11], "outputs (12-14)": [12, 13, 14]}


def main():
    path, gen = sys.argv[1], int(sys.argv[2])
    sample = int(sys.argv[3]) if len(sys.argv) > 3 else 1000
    con = sqlite3.connect(f"file:{path}?mode=ro", uri=True)
    (kb_id, width, channels, delta), = con.execute(
        "SELECT id, segment_width, channels, delta FROM kb WHERE name = 'run'").fetchall()
    rows = con.execute("SELECT first_generation, segment_values FROM kb_segment WHERE kb_id = ? ORDER BY id",
                       (kb_id,)).fetchall()
    gens = np.array([r[0] for r in rows])
    values = np.array([decode(r[1], width, channels) for r in rows], dtype=np.float32).reshape(
        len(rows), width, channels)
    before = values[gens < gen].astype(np.float64)
    new = values[gens == gen].astype(np.float64)
    rng = np.random.default_rng(1)
    new = new[rng.choice(len(new), size=min(sample, len(new)), replace=False)]
    flat_before = before.reshape(len(before), -1)
    share = {k: 0.0 for k in GROUPS}
    dists = []
    for seg in new:
        d2 = ((flat_before - seg.reshape(-1)) ** 2).sum(axis=1)
        j = int(np.argmin(d2))
        diff2 = ((before[j] - seg) ** 2).sum(axis=0)  # per channel
        dists.append(np.sqrt(d2[j]))
        for k, chans in GROUPS.items():
            share[k] += diff2[chans].sum() / d2[j]
    dists = np.array(dists)
    print(f"{path}: {len(new)} of the segments inserted at generation {gen}, "
          f"against {len(before)} inserted before (delta {delta})")
    print(f"distance to the nearest earlier segment: median {np.median(dists):.2f}, "
          f"quartiles {np.percentile(dists, 25):.2f} / {np.percentile(dists, 75):.2f}, "
          f"below delta {np.mean(dists < delta):.1%}")
    for k in GROUPS:
        print(f"  {k:34s} {share[k] / len(new):6.1%} of the squared distance")


if __name__ == "__main__":
    main()
