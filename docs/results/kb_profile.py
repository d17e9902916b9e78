#!/usr/bin/env python3
"""Profile of a stepstone knowledge base: size, counts, constant segments,
per-channel ranges and the spread of average rewards.

Usage: kb_profile.py FILE.db [KB_NAME]   (Python 3 standard library only)
"""
import sqlite3
import sys
from collections import Counter

from segments import decode


def main():
    if len(sys.argv) not in (2, 3):
        sys.exit("usage: kb_profile.py FILE.db [KB_NAME]")
    con = sqlite3.connect(f"file:{sys.argv[1]}?mode=ro", uri=True)
    kbs = con.execute("SELECT id, name, segment_width, channels, delta FROM kb").fetchall()
    if len(sys.argv) == 3:
        kbs = [k for k in kbs if k[1] == sys.argv[2]]
    if len(kbs) != 1:
        sys.exit(f"{sys.argv[1]}: name one KB among {[k[1] for k in kbs]}")
    kb_id, name, width, channels, delta = kbs[0]
    n = 0
    constant = 0
    once = 0
    lo = [float("inf")] * channels
    hi = [float("-inf")] * channels
    averages = Counter()
    first_gen = Counter()
    for cum, count, blob, gen in con.execute(
            "SELECT cum_reward, count, segment_values, first_generation FROM kb_segment WHERE kb_id = ?",
            (kb_id,)):
        n += 1
        values = decode(blob, width, channels)
        rows = [values[r * channels:(r + 1) * channels] for r in range(width)]
        if all(row == rows[0] for row in rows):
            constant += 1
        for row in rows:
            for c, v in enumerate(row):
                lo[c] = min(lo[c], v)
                hi[c] = max(hi[c], v)
        once += count == 1
        averages[round(cum / count, 2)] += 1
        first_gen[gen] += 1
    print(f"kb {name}: {n} segments, width {width}, channels {channels}, delta {delta}")
    print(f"seen once: {once} ({once / max(n, 1):.1%}); constant (20 equal rows): {constant}")
    print("channel ranges: " + " ".join(f"{c}:[{lo[c]:.3g},{hi[c]:.3g}]" for c in range(channels)))
    print("inserted per generation: " + " ".join(f"{g}:{k}" for g, k in sorted(first_gen.items())))
    print("average reward (rounded to 0.01): " +
          " ".join(f"{a:g}:{k}" for a, k in sorted(averages.items())))


if __name__ == "__main__":
    main()
