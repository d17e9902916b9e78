#!/usr/bin/env python3
"""A search written in numpy whose fitness a stepstone knowledge base shapes.

A linear policy (3 outputs = sigmoid(W [inputs, 1])) is evolved by a simple
evolution strategy on the target task. Its fitness is the `sum` treatment's:
the task reward plus the policy's r_max over the KB's largest average, worth
at most (almost) one ball. The KB is one that `stepstone` wrote (a run file,
or `stepstone kb export`); before the search, the r_max this script computes
for the run's best stored policy is checked against `stepstone shape`.

    stepstone evolve --config examples/source_quick.json --db source.db
    PYTHONPATH=build/release/python /usr/bin/python3 examples/python/shaped_search.py \\
        --kb source.db --run source.db
"""

import argparse
import json
import os
import subprocess
import sys

import numpy as np

import stepstone

SUM_MARGIN = 1.0 / 1024.0  # the `sum` bonus stays below one ball (docs/transfer.md)


def check_r_max(kb, kb_path, run_path, stepstone_binary):
    """r_max of the run's best stored policy, here and by `stepstone shape`."""
    behaviour = stepstone.Run(run_path).replay("best")["behaviour"]
    mine = kb.lookup(behaviour).r_max
    shaped = subprocess.run([stepstone_binary, "shape", "--kb", kb_path, "--run", run_path, "--json"],
                            capture_output=True, text=True)
    if shaped.returncode != 0:
        sys.exit(f"shaped_search: stepstone shape failed: {shaped.stderr.strip()}")
    theirs = json.loads(shaped.stdout)["r_max"]
    if mine != theirs:
        sys.exit(f"shaped_search: r_max check failed: {mine!r} here, {theirs!r} from stepstone shape")
    print(f"r_max check: ok ({mine:.6g} for the best policy of {run_path}, as stepstone shape says)")


def evaluate(weights, task, kb):
    """Runs the linear policy on `task`; returns (fitness, reward, r_max)."""
    episode = stepstone.Episode(task)
    observation, done = episode.observation, False
    while not done:
        activation = weights[:, :-1] @ observation + weights[:, -1]
        observation, done = episode.step(1.0 / (1.0 + np.exp(-activation)))
    result = episode.finish()
    r_max = kb.lookup(result["behaviour"]).r_max
    bonus = r_max / kb.max_average if kb.max_average > 0 else 0.0
    fitness = result["reward"] + bonus * (1.0 - SUM_MARGIN) / task.reward_divisor
    return fitness, result["reward"], r_max


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     epilog="example: shaped_search.py --kb source.db --run source.db",
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--kb", required=True, help="KB or run file written by stepstone")
    parser.add_argument("--kb-name", default=None, help="which KB of the file (default: its only one)")
    parser.add_argument("--run", required=True, help="run file whose best policy checks r_max against stepstone shape")
    parser.add_argument("--generations", type=int, default=10)
    parser.add_argument("--population", type=int, default=8)
    parser.add_argument("--steps", type=int, default=1000, help="steps of each start of the target task")
    parser.add_argument("--starts", type=int, default=1)
    parser.add_argument("--sigma", type=float, default=0.5, help="mutation step of the strategy")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--stepstone", default=os.environ.get("STEPSTONE_BINARY", "stepstone"),
                        help="the stepstone binary (default: $STEPSTONE_BINARY, else on PATH)")
    args = parser.parse_args()
    if args.generations < 1 or args.population < 2:
        parser.error("--generations must be >= 1 and --population >= 2")

    try:
        kb = stepstone.KnowledgeBase.open(args.kb, args.kb_name)
    except stepstone.Error as error:
        sys.exit(f"shaped_search: {error}")
    print(f"{kb}, largest average {kb.max_average:.6g}")
    check_r_max(kb, args.kb, args.run, args.stepstone)

    task = stepstone.Task("target", steps_per_start=args.steps, starts=args.starts)
    rng = np.random.default_rng(args.seed)
    # a (mu, lambda) strategy with mu = population / 2, recombined by the mean
    mean = rng.normal(0.0, 1.0, size=(3, 13))
    best = (-np.inf, 0.0, 0.0)
    for generation in range(args.generations):
        offspring = [mean + args.sigma * rng.normal(size=mean.shape) for _ in range(args.population)]
        scored = sorted(((evaluate(w, task, kb), k) for k, w in enumerate(offspring)), key=lambda s: -s[0][0])
        elite = [offspring[k] for _, k in scored[: args.population // 2]]
        mean = np.mean(elite, axis=0)
        top = scored[0][0]
        best = max(best, top)
        print(f"generation {generation}: best fitness {top[0]:.5f} (reward {top[1]:.4f}, r_max {top[2]:.4g})")
    print(f"best fitness {best[0]:.5f}: reward {best[1]:.4f}, r_max {best[2]:.4g}")


if __name__ == "__main__":
    main()
