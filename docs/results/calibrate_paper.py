#!/usr/bin/python3
"""Calibrate stepstone's KB against the paper's (Doncieux, "Transfer Learning for
Direct Policy Search: A Reward Shaping Approach"): the delta rule under three
readings, the KB size and zero-average share per delta, and whether the best
policy's segments outrank those of its relatives, for two encodings of a behaviour.

Usage:
  calibrate_paper.py RUN.db [--csv OUT.csv] [--max-policies N] [--every K] [--min-size-delta D]
                            [--counting occurrence|policy ...] [--relatives-window G]
  calibrate_paper.py --self-test
Needs numpy and the stepstone module (default build below; override with the
STEPSTONE_PYTHON environment variable naming the folder that holds it).

Encodings (a behaviour is the first start's steps x 15 float32 matrix):
  today  the raw floats, as stepstone stores them;
  bits   the original code's 15-bit record: lasers (0-2) and outputs (12-14) become
         1 where strictly > 0.5 (laser: wall nearer than half the range), else 0;
         lights, bumpers and carrying (3-11) are already 0/1 and kept.
Delta-rule readings, on the run's best policy (replay('best')), k = 20 neighbours:
  segments       its rows//20 non-overlapping segments, each one's mean distance to its
                 20 nearest other segments, averaged (= `stepstone kb calibrate`);
  windows_excl   every window of 20 rows at stride 1, each one's mean distance to its 20
                 nearest windows that do not overlap it (|i - j| >= 20), averaged;
  windows_incl   the same with every other window a candidate (|i - j| >= 1).
KBs: one per (encoding, counting, delta) with delta in {1.83 (the paper's, reading
'paper')} and each reading's delta rounded to 3 decimals; each observes the STORED
genomes of the run (first front + best per generation, not every evaluated policy),
replayed (first start), in individual-id order, each with its stored reward.
Relatives: the other stored policies of the best's generation and the G (50) before it.

CSV: one row per (encoding, counting, reading, measure); columns
  run_file, policies (stored genomes observed), encoding, counting ('-' where it
  does not apply), reading (segments | windows_excl | windows_incl | paper), delta,
  measure, value, n, where measure is
  delta_rule        the reading's delta (value); n = segments or windows averaged
  kb_segments       segments in the KB at that delta; n = policies observed
  kb_zero_share     share of those segments whose average reward is exactly 0
  a12_segments      (delta 1.83) Vargha-Delaney A12 of the best's per-segment matched
                    averages (lookup) against the pooled ones of its relatives:
                    P(best > other) + 0.5 P(equal); n = relatives
  a12_r_max         (delta 1.83) the same for the best's r_max against the relatives'
                    r_max (the share of relatives it beats, ties half); n = relatives
  best_r_max        (delta 1.83) the best's r_max; n = 1
"""
import argparse
import csv
import os
import sqlite3
import sys
import time

import numpy as np

WIDTH, K, PAPER_DELTA = 20, 20, 1.83
THRESHOLDED = [0, 1, 2, 12, 13, 14]  # lasers and network outputs
READINGS = ("segments", "windows_excl", "windows_incl")


# ---------------------------------------------------------------- encodings
def to_bits(b):
    """The original code's bits encoding of a (steps x 15) behaviour, float32."""
    out = np.array(b, dtype=np.float32, copy=True)
    out[:, THRESHOLDED] = (out[:, THRESHOLDED] > 0.5).astype(np.float32)
    return out


ENCODINGS = {"today": lambda b: np.asarray(b, dtype=np.float32), "bits": to_bits}


# ---------------------------------------------------------------- delta rule
def window_distances(b, width=WIDTH):
    """Euclidean distances (float64) between all windows of `width` rows at stride 1.

    Exact: the row-to-row squared distances are summed channel by channel (no Gram
    trick), then a window pair's squared distance is the sum of `width` of them
    along a diagonal: W2[i, j] = sum_t D[i + t, j + t]."""
    x = np.asarray(b, dtype=np.float64)
    rows = x.shape[0]
    d = np.zeros((rows, rows))
    for c in range(x.shape[1]):
        diff = x[:, c, None] - x[None, :, c]
        d += diff * diff
    n = rows - width + 1
    w2 = d[:n, :n].copy()
    for t in range(1, width):
        w2 += d[t:t + n, t:t + n]
    del d
    return np.sqrt(w2, out=w2)


def knn_mean(dist, k=K):
    """Mean over rows of each row's mean of its k smallest finite entries (inf = excluded)."""
    finite = np.isfinite(dist).sum(axis=1).min()
    k = min(k, int(finite))
    if k < 1:
        raise ValueError("no candidate neighbour")
    return float(np.partition(dist, k - 1, axis=1)[:, :k].mean(axis=1).mean())


def delta_readings(b, width=WIDTH, k=K):
    """{reading: (delta, items averaged)} for one behaviour."""
    w = window_distances(b, width)
    n = w.shape[0]
    out = {}
    starts = np.arange(np.asarray(b).shape[0] // width) * width  # non-overlapping segments
    seg = w[np.ix_(starts, starts)].copy()
    np.fill_diagonal(seg, np.inf)
    out["segments"] = (knn_mean(seg, k), len(starts))
    gap = np.abs(np.arange(n)[:, None] - np.arange(n)[None, :])
    for name, min_gap in (("windows_excl", width), ("windows_incl", 1)):
        masked = np.where(gap >= min_gap, w, np.inf)
        out[name] = (knn_mean(masked, k), n)
        del masked
    return out


# ---------------------------------------------------------------- A12
def a12(x, y):
    """Vargha-Delaney A12 = P(X > Y) + 0.5 P(X = Y) over all pairs."""
    x, ys = np.asarray(x, dtype=np.float64), np.sort(np.asarray(y, dtype=np.float64))
    if len(x) == 0 or len(ys) == 0:
        return float("nan")
    less = np.searchsorted(ys, x, side="left")
    equal = np.searchsorted(ys, x, side="right") - less
    return float((less + 0.5 * equal).sum() / (len(x) * len(ys)))


# ---------------------------------------------------------------- self-test
def self_test():
    rng = np.random.default_rng(7)
    b = np.zeros((200, 15), dtype=np.float32)
    b[:, 0:3] = np.where(rng.random((200, 3)) < 0.3, 0, rng.random((200, 3)))  # lasers, some 0
    b[:, 3:12] = rng.random((200, 9)) < 0.3                                      # binary
    b[:, 12:15] = rng.random((200, 3))                                           # outputs
    ok = True
    for enc, f in ENCODINGS.items():
        e = f(b)
        fast = delta_readings(e)
        # brute force: windows materialised, np.linalg.norm, explicit loops
        x = e.astype(np.float64)
        n = x.shape[0] - WIDTH + 1
        wins = [x[i:i + WIDTH].ravel() for i in range(n)]
        dist = np.array([[np.linalg.norm(wins[i] - wins[j]) for j in range(n)] for i in range(n)])
        segs = range(0, x.shape[0] // WIDTH * WIDTH, WIDTH)
        brute = {
            "segments": np.mean([np.mean(sorted(dist[i, j] for j in segs if j != i)[:K]) for i in segs]),
            "windows_excl": np.mean([np.mean(sorted(dist[i, j] for j in range(n) if abs(i - j) >= WIDTH)[:K])
                                     for i in range(n)]),
            "windows_incl": np.mean([np.mean(sorted(dist[i, j] for j in range(n) if j != i)[:K])
                                     for i in range(n)]),
        }
        for r in READINGS:
            err = abs(fast[r][0] - brute[r])
            ok &= err < 1e-9
            print(f"self-test {enc:5s} {r:13s} fast {fast[r][0]:.12f} brute {brute[r]:.12f} |diff| {err:.1e}")
    bits = to_bits(b)
    expect = b.copy()
    for i, j in np.ndindex(b.shape):
        if j in THRESHOLDED:
            expect[i, j] = 1.0 if b[i, j] > 0.5 else 0.0
    ok &= bool(np.array_equal(bits, expect)) and set(np.unique(bits)) <= {0.0, 1.0}
    print(f"self-test bits encoding elementwise: {'ok' if np.array_equal(bits, expect) else 'MISMATCH'}")
    x, y = rng.integers(0, 4, 30), rng.integers(0, 4, 50)  # with ties
    brute = np.mean([(xi > yj) + 0.5 * (xi == yj) for xi in x for yj in y])
    ok &= abs(a12(x, y) - brute) < 1e-12
    print(f"self-test A12 {a12(x, y):.12f} brute {brute:.12f}")
    print("self-test", "PASSED" if ok else "FAILED")
    return 0 if ok else 1


# ---------------------------------------------------------------- the run
def load_module():
    sys.path.insert(0, os.environ.get("STEPSTONE_PYTHON", "/work/exp/src-9c53c41/build/release/python"))
    import stepstone
    return stepstone


def kb_maker(stepstone, countings):
    """A function (delta, counting) -> empty KB; exits if 'policy' counting is unavailable."""
    try:
        stepstone.KnowledgeBase(width=WIDTH, channels=15, delta=PAPER_DELTA, counting="occurrence")
        supported = True
    except TypeError:  # this build's constructor has no `counting` argument
        supported = False
    if not supported and any(c != "occurrence" for c in countings):
        sys.exit(f"calibrate_paper: the stepstone module at {stepstone.__file__} has no "
                 "KnowledgeBase(counting=...): only --counting occurrence works with it; "
                 "point STEPSTONE_PYTHON at a build that has policy counting")

    def make(delta, counting):
        extra = {"counting": counting} if supported else {}
        return stepstone.KnowledgeBase(width=WIDTH, channels=15, delta=delta, match="within_delta", **extra)
    return make


def stored_policies(path, run_id):
    """(individual_id, generation, reward) of every stored genome, in id order."""
    con = sqlite3.connect(f"file:{path}?mode=ro", uri=True)
    try:
        return con.execute(
            "SELECT g.individual_id, i.generation, i.reward FROM genome g JOIN individual i "
            "ON i.run_id = g.run_id AND i.id = g.individual_id WHERE g.run_id = ? "
            "ORDER BY g.individual_id", (run_id,)).fetchall()
    finally:
        con.close()


def analyse(args):
    stepstone = load_module()
    make_kb = kb_maker(stepstone, args.counting)
    run = stepstone.Run(args.run)
    name = os.path.basename(args.run)
    policies = stored_policies(args.run, run.id)
    if args.every > 1:
        policies = policies[::args.every]
    if args.max_policies is not None:
        policies = policies[:args.max_policies]
    best = run.replay("best")
    best_id, best_gen = best["individual_id"], best["generation"]
    relatives = {i for i, g, _ in policies
                 if best_gen - args.relatives_window <= g <= best_gen and i != best_id}
    rows = []  # (encoding, counting, reading, delta, measure, value, n)

    # 1. the delta rule, three readings, per encoding
    kbs, deltas = {}, {}
    for enc, f in ENCODINGS.items():
        readings = delta_readings(f(best["behaviour"]))
        deltas[enc] = {"paper": PAPER_DELTA}
        for r in READINGS:
            rows.append((enc, "-", r, readings[r][0], "delta_rule", readings[r][0], readings[r][1]))
            deltas[enc][r] = round(readings[r][0], 3)
        for c in args.counting:
            for d in set(deltas[enc].values()):
                # a second counting rule changes no size: its KB is built at the paper's delta only,
                # for the zero share and A12; deltas below --min-size-delta are not sized (slow)
                if d == PAPER_DELTA or (c == args.counting[0] and d >= args.min_size_delta):
                    kbs[(enc, c, d)] = make_kb(d, c)

    # 2. observe the stored genomes in id order (one replay each, all KBs fed)
    cache, t0 = {}, time.time()
    for done, (ind, gen, reward) in enumerate(policies, 1):
        b = run.replay(int(ind))["behaviour"]
        if ind in relatives:
            cache[ind] = b
        encoded = {enc: f(b) for enc, f in ENCODINGS.items()}
        for (enc, _, _), kb in kbs.items():
            kb.observe(encoded[enc], reward=float(reward), run=name, generation=int(gen))
        if done % 200 == 0 or done == len(policies):
            sizes = " ".join(f"{e}/{c}/{d:g}:{len(kb)}" for (e, c, d), kb in sorted(kbs.items()))
            print(f"[{done}/{len(policies)} policies, {time.time() - t0:.0f} s] {sizes}", file=sys.stderr)
    for enc in ENCODINGS:
        for c in args.counting:
            for r, d in deltas[enc].items():
                if (enc, c, d) not in kbs:
                    continue
                kb = kbs[(enc, c, d)]
                averages = kb.records["average"]
                zero = float(np.mean(averages == 0.0)) if len(kb) else float("nan")
                rows.append((enc, c, r, d, "kb_segments", len(kb), len(policies)))
                rows.append((enc, c, r, d, "kb_zero_share", zero, len(policies)))

    # 3. the best's segments against its relatives', in the 1.83 KBs
    for enc, f in ENCODINGS.items():
        for c in args.counting:
            kb = kbs[(enc, c, PAPER_DELTA)]
            mine = kb.lookup(f(best["behaviour"]))
            theirs = [kb.lookup(f(b)) for b in cache.values()]
            pooled = np.concatenate([t.averages for t in theirs]) if theirs else np.array([])
            rows.append((enc, c, "paper", PAPER_DELTA, "a12_segments", a12(mine.averages, pooled), len(theirs)))
            rows.append((enc, c, "paper", PAPER_DELTA, "a12_r_max",
                         a12([mine.r_max], [t.r_max for t in theirs]), len(theirs)))
            rows.append((enc, c, "paper", PAPER_DELTA, "best_r_max", mine.r_max, 1))
    return name, len(policies), best, len(relatives & set(cache)), rows


def report(name, n_policies, best, n_rel, rows, csv_path, window):
    print(f"run file {name}: {n_policies} stored genomes observed (first fronts + best per "
          f"generation, not every evaluated policy), replayed, first start")
    print(f"best policy: individual {best['individual_id']} of generation {best['generation']}, "
          f"stored reward {best['stored_reward']:g}; {n_rel} relatives (stored, generations "
          f"{max(0, best['generation'] - window)}..{best['generation']})")
    header = ("encoding", "counting", "reading", "delta", "measure", "value", "n")
    print(f"{header[0]:8s} {header[1]:10s} {header[2]:13s} {header[3]:>8s} {header[4]:14s} "
          f"{header[5]:>12s} {header[6]:>7s}")
    for enc, c, r, d, m, v, n in rows:
        val = f"{v:d}" if isinstance(v, int) else f"{v:.6f}"
        print(f"{enc:8s} {c:10s} {r:13s} {d:8.3f} {m:14s} {val:>12s} {n:7d}")
    if csv_path:
        with open(csv_path, "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(("run_file", "policies") + header)
            for enc, c, r, d, m, v, n in rows:
                w.writerow((name, n_policies, enc, c, r, repr(float(d)), m,
                            v if isinstance(v, int) else repr(float(v)), n))
        print(f"wrote {csv_path}")


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("run", nargs="?", help="run file written by `stepstone evolve`")
    p.add_argument("--csv", help="write the rows to this CSV")
    p.add_argument("--max-policies", type=int, help="observe only the first N stored genomes (quick tests)")
    p.add_argument("--min-size-delta", type=float, default=0.0,
                   help="size no KB at a reading's delta below this (small deltas make large, slow KBs)")
    p.add_argument("--every", type=int, default=1,
                   help="observe every K-th stored genome in id order (a sample spread over the whole run)")
    p.add_argument("--counting", nargs="+", default=["occurrence"], choices=("occurrence", "policy"),
                   help="KB counting rule(s); 'policy' needs a module with KnowledgeBase(counting=)")
    p.add_argument("--relatives-window", type=int, default=50, help="generations before the best's (50)")
    p.add_argument("--self-test", action="store_true", help="check the fast code against brute force")
    args = p.parse_args()
    if args.self_test:
        return self_test()
    if not args.run:
        p.error("RUN.db is required (or --self-test)")
    args.counting = list(dict.fromkeys(args.counting))
    name, n, best, n_rel, rows = analyse(args)
    report(name, n, best, n_rel, rows, args.csv, args.relatives_window)
    return 0


if __name__ == "__main__":
    sys.exit(main())
