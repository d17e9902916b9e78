#!/usr/bin/env python3
"""How fast Python looks policies up in a knowledge base, against the same
lookups in a C++ loop of the same process.

The KB is grown as a source run grows one: the genomes of a source run
(bench/data/source_genomes.jsonl, the `bench shaped-*` cases' fixture) are
evaluated on the paper's source task and observed in order. The policies
looked up are target-task evaluations of random genomes: 4000 steps, 200
segments each. Prints the rate of KnowledgeBase.lookup() and r_max() called
from Python, the rate of the same calls in C++, and their ratio.

    PYTHONPATH=build/release/python /usr/bin/python3 examples/python/lookup_speed.py
"""

import argparse
import json
import os
import sys
import time

import numpy as np

import stepstone

HERE = os.path.dirname(os.path.abspath(__file__))
DEFAULT_GENOMES = os.path.join(HERE, "..", "..", "bench", "data", "source_genomes.jsonl")


def source_kb(genomes_path, delta, count):
    task = stepstone.Task("source")
    kb = stepstone.KnowledgeBase(delta=delta)
    with open(genomes_path) as f:
        genomes = [json.loads(line) for line in f if line.strip()][:count]
    for k, genome in enumerate(genomes):
        result = stepstone.evaluate(task, genome)
        kb.observe(result["behaviour"], result["reward"], run="source", generation=k)
    return kb


def rate(calls, seconds):
    return calls / seconds if seconds > 0 else float("inf")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     epilog="example: lookup_speed.py --delta 3.84 --policies 100")
    parser.add_argument("--genomes", default=DEFAULT_GENOMES, help="JSON lines of source genomes")
    parser.add_argument("--source-policies", type=int, default=500, help="genomes observed into the KB")
    parser.add_argument("--delta", type=float, default=1.83)
    parser.add_argument("--policies", type=int, default=100, help="target policies looked up")
    parser.add_argument("--repeats", type=int, default=3, help="timings kept: the fastest of this many")
    parser.add_argument("--min-ratio", type=float, default=0.0,
                        help="exit 1 when a Python rate falls below this fraction of the C++ rate")
    args = parser.parse_args()

    kb = source_kb(args.genomes, args.delta, args.source_policies)
    target = stepstone.Task("target")
    behaviours = np.stack([stepstone.evaluate(target, stepstone.random_genome(1000 + k))["behaviour"]
                           for k in range(args.policies)])
    print(f"{kb}; {args.policies} target policies of {behaviours.shape[1] // kb.width} segments")

    short = False
    for name, r_max_only in (("lookup", False), ("r_max", True)):
        call = kb.r_max if r_max_only else kb.lookup
        call(behaviours[0])  # builds what the first call builds (the salient index) before timing
        python_seconds, cpp_seconds = [], []
        for _ in range(args.repeats):
            start = time.perf_counter()
            for b in behaviours:
                call(b)
            python_seconds.append(time.perf_counter() - start)
            cpp_seconds.append(stepstone._time_lookups(kb, behaviours, r_max_only))
        python_rate = rate(len(behaviours), min(python_seconds))
        cpp_rate = rate(len(behaviours), min(cpp_seconds))
        ratio = python_rate / cpp_rate
        short |= ratio < args.min_ratio
        print(f"{name:7s} python {python_rate:9.1f} policies/s   C++ {cpp_rate:9.1f} policies/s   "
              f"ratio {ratio:.3f}")
    sys.exit(1 if short else 0)


if __name__ == "__main__":
    main()
