"""stepstone.KnowledgeBase shared by Python threads: observe, lookup, r_max,
merge and save mixed from four threads, twenty times over, against a serial
replay of the same calls (issue: "double free or corruption" when observe ran
without a lock).

The threads observe behaviours in four regions of space far apart (more than
delta), and merge a KB of a fifth region: no call's matches depend on another
thread's, so every interleaving the lock may admit gives the same KB up to the
order of segment ids, which the check ignores (it compares the segments with
their statistics as a sorted list)."""

import os
import tempfile
import threading
import unittest

import numpy as np

import stepstone

CALLS = 200
ROUNDS = 20
STEPS = 400  # 20 segments of 20 steps: long enough for threads to overlap inside observe


def behaviour(region, k):
    """A behaviour of region `region`: 1 channel offset by 100 x region, so regions stay apart."""
    rng = np.random.default_rng(region * 100003 + k)
    # a few prototypes per region, so observations both insert and credit
    base = np.repeat(rng.integers(0, 4, size=(STEPS // 20, 1)), 20, axis=0).astype(np.float32)
    noise = rng.random((STEPS, 15), dtype=np.float32) * 0.05
    return base + noise + 100.0 * region


def contents(kb):
    """The KB as a sorted list of (segment bytes, count, cum_reward), ids ignored."""
    records = kb.records
    segments = np.array(kb.segments)
    return sorted((segments[i].tobytes(), int(records["count"][i]), float(records["cum_reward"][i]))
                  for i in range(len(kb)))


class SharedKb(unittest.TestCase):
    def test_four_threads_mixing_every_call_equal_a_serial_replay(self):
        other = stepstone.KnowledgeBase(width=20, channels=15, delta=0.5)
        for k in range(5):
            other.observe(behaviour(5, k), reward=0.5, run="other")
        with tempfile.TemporaryDirectory(prefix="stepstone-threads-") as folder:
            for round_ in range(ROUNDS):
                kb = stepstone.KnowledgeBase(width=20, channels=15, delta=0.5)
                errors = []
                start = threading.Barrier(4)

                def work(region):
                    try:
                        start.wait()
                        for k in range(CALLS):
                            b = behaviour(region, k)
                            step = k % 5
                            if step in (0, 1):
                                kb.observe(b, reward=0.25 * (k % 4), run=f"thread-{region}", generation=k)
                            elif step == 2:
                                found = kb.lookup(b)
                                assert 0.0 <= found.r_max <= 0.75, found.r_max
                            elif step == 3:
                                assert 0.0 <= kb.r_max(b) <= 0.75
                            elif region == 0 and k % 50 == 4:
                                kb.merge(other)
                            elif k % 40 == 4:
                                kb.save(os.path.join(folder, f"save-{region}.db"), force=True)
                            else:
                                len(kb)
                    except Exception as error:  # noqa: BLE001 - collected and reported below
                        errors.append(repr(error))

                threads = [threading.Thread(target=work, args=(region,)) for region in range(4)]
                for t in threads:
                    t.start()
                for t in threads:
                    t.join()
                self.assertEqual(errors, [], f"round {round_}")

                # the same calls one thread after another
                serial = stepstone.KnowledgeBase(width=20, channels=15, delta=0.5)
                for region in range(4):
                    for k in range(CALLS):
                        step = k % 5
                        if step in (0, 1):
                            serial.observe(behaviour(region, k), reward=0.25 * (k % 4), run=f"thread-{region}",
                                           generation=k)
                        elif step == 4 and region == 0 and k % 50 == 4:
                            serial.merge(other)
                self.assertEqual(len(kb), len(serial), f"round {round_}")
                self.assertEqual(contents(kb), contents(serial), f"round {round_}")
                self.assertEqual(sorted((s["run"], s["policies"]) for s in kb.sources),
                                 sorted((s["run"], s["policies"]) for s in serial.sources))
                # a file saved mid-run is whole
                saved = stepstone.KnowledgeBase.open(os.path.join(folder, "save-1.db"))
                self.assertLessEqual(len(saved), len(kb))


if __name__ == "__main__":
    unittest.main()
