"""stepstone.KnowledgeBase against independent expectations: the files and
answers of the stepstone CLI, a file read back with Python's sqlite3, and the
paper's rule computed by hand in numpy."""

import json
import os
import re
import subprocess
import unittest
import urllib.request

import numpy as np

import stepstone
from support import BINARY, TINY_SOURCE, TempCase, cli, cli_json, stored_kb, write_run


def behaviour(seed, steps=200, channels=15):
    return np.random.default_rng(seed).random((steps, channels), dtype=np.float32)


class Rule(unittest.TestCase):
    def test_observe_follows_the_papers_rule(self):
        # by hand: 3 segments of width 2 in 1 channel; delta 1.5
        kb = stepstone.KnowledgeBase(width=2, channels=1, delta=1.5)
        b = np.array([[0], [0], [1], [0], [5], [5]], dtype=np.float32)
        # segment (0,0) inserted; (1,0) is at distance 1 < 1.5: credited; (5,5) inserted
        self.assertEqual(kb.observe(b, 0.5, run="a"), {"matched": 1, "inserted": 2})
        rec = kb.records
        np.testing.assert_array_equal(rec["count"], [2, 1])
        np.testing.assert_array_equal(rec["cum_reward"], [1.0, 0.5])
        np.testing.assert_array_equal(kb.segments.reshape(2, 2), [[0, 0], [5, 5]])
        # a policy near the second segment only: r_max is its average; none is -1 with 0
        found = kb.lookup(np.array([[9], [9], [5], [6]], dtype=np.float32))
        np.testing.assert_array_equal(found.ids, [-1, 1])
        np.testing.assert_array_equal(found.distances, [0.0, 1.0])
        self.assertEqual(found.r_max, 0.5)
        self.assertEqual(kb.r_max(np.array([[9], [9], [5], [6]], dtype=np.float32)), 0.5)

    def test_float64_input_is_converted(self):
        kb = stepstone.KnowledgeBase(width=20, channels=15)
        b = behaviour(1)
        kb.observe(b.astype(np.float64), 1.0)
        np.testing.assert_array_equal(kb.segments.reshape(-1, 15), b)

    def test_bad_input_raises_one_line(self):
        kb = stepstone.KnowledgeBase(width=20, channels=15)
        with self.assertRaisesRegex(ValueError, "has 14 columns, the knowledge base has 15 channels"):
            kb.observe(np.zeros((40, 14), dtype=np.float32), 1.0)
        with self.assertRaisesRegex(ValueError, "must be a .steps x channels. matrix, got 1 dimension"):
            kb.lookup(np.zeros(300, dtype=np.float32))
        bad = behaviour(2)
        bad[25, 3] = np.nan
        with self.assertRaisesRegex(stepstone.DataError, "non-finite"):
            kb.observe(bad, 1.0)
        self.assertEqual(len(kb), 0, "a refused observation leaves the KB unchanged")
        with self.assertRaises(stepstone.ConfigError):
            stepstone.KnowledgeBase(delta=-1)
        with self.assertRaisesRegex(stepstone.ConfigError, "match"):
            stepstone.KnowledgeBase(match="closest")

    def test_views_pin_the_segments(self):
        kb = stepstone.KnowledgeBase(width=20, channels=15)
        kb.observe(behaviour(1), 1.0)
        view = kb.segments
        self.assertFalse(view.flags.writeable)
        self.assertFalse(view.flags.owndata, "segments must view the KB's memory, not a copy")
        with self.assertRaises(BufferError):
            kb.observe(behaviour(2), 1.0)
        copy = np.array(view)
        del view
        kb.observe(behaviour(2), 1.0)
        self.assertEqual(len(kb), 20)
        np.testing.assert_array_equal(kb.segments[:10], copy)
        # a view keeps its KB alive
        kb2 = stepstone.KnowledgeBase(width=20, channels=15)
        kb2.observe(behaviour(3), 1.0)
        view = kb2.segments
        del kb2
        np.testing.assert_array_equal(view.reshape(-1, 15), behaviour(3))


class Files(TempCase):
    @classmethod
    def setUpClass(cls):
        import tempfile
        cls._run_dir = tempfile.TemporaryDirectory(prefix="stepstone-py-run-")
        cls.run_file = write_run(cls._run_dir.name)

    @classmethod
    def tearDownClass(cls):
        cls._run_dir.cleanup()

    def test_a_cli_kb_opens_with_the_same_segments_and_averages(self):
        out = self.path("kb.db")
        cli("kb", "export", self.run_file, "--out", out)
        kb = stepstone.KnowledgeBase.open(out)
        segments, cum, count = stored_kb(out)
        self.assertGreater(len(kb), 10)
        np.testing.assert_array_equal(kb.segments, segments)
        np.testing.assert_array_equal(kb.records["average"], cum / count)
        np.testing.assert_array_equal(kb.records["count"], count)
        self.assertEqual(kb.name, "run")
        self.assertEqual((kb.width, kb.channels, kb.delta, kb.match), (20, 15, 1.0, "within_delta"))
        # the run file's own KB opens too
        np.testing.assert_array_equal(stepstone.KnowledgeBase.open(self.run_file).segments, segments)

    def python_kb(self):
        # a KB built in Python from the run's policies of generations 0-2, replayed, each with its own
        # reward, so that later policies match segments of different averages (delta 1.0, as the run's)
        run = stepstone.Run(self.run_file)
        kb = stepstone.KnowledgeBase(width=20, channels=15, delta=1.0)
        for row in run.individuals()[run.individuals()["generation"] < 3]:
            kb.observe(run.replay(int(row["id"]))["behaviour"], reward=0.01 * (int(row["id"]) + 1), run="py",
                       generation=int(row["generation"]))
        return kb

    def test_a_python_kb_is_read_by_the_cli_and_shapes_as_stepstone_shape(self):
        kb = self.python_kb()
        out = self.path("py.db")
        kb.save(out, name="from-python")
        stats = cli_json("kb", "stats", out, "--json")
        self.assertEqual(stats["segments"], len(kb))
        segments, cum, count = stored_kb(out)
        np.testing.assert_array_equal(segments, kb.segments)
        np.testing.assert_array_equal(cum, kb.records["cum_reward"])

        last = stepstone.Run(self.run_file).individuals(generation=4)["id"]
        for individual in (int(last[0]), int(last[5])):
            shaped = cli_json("shape", "--kb", out, "--run", self.run_file, "--individual", individual, "--json")
            mine = kb.lookup(stepstone.Run(self.run_file).replay(individual)["behaviour"])
            self.assertEqual(mine.r_max, shaped["r_max"])
            ids = [-1 if s["kb_segment_id"] is None else s["kb_segment_id"] for s in shaped["segments"]]
            np.testing.assert_array_equal(mine.ids, ids)
            np.testing.assert_array_equal(mine.distances, [s["distance"] for s in shaped["segments"]])
            np.testing.assert_array_equal(mine.averages, [s["average_reward"] for s in shaped["segments"]])
            # a lookup worth checking: matches with different averages, and a miss or a segment of its own
            self.assertGreater(len(set(mine.averages)), 1, individual)

    def test_save_refuses_an_existing_file(self):
        out = self.path("taken.db")
        with open(out, "w") as f:
            f.write("precious")
        with self.assertRaisesRegex(stepstone.ConfigError, "exists"):
            stepstone.KnowledgeBase(width=20, channels=15).save(out)
        with open(out) as f:
            self.assertEqual(f.read(), "precious")
        with self.assertRaisesRegex(stepstone.DatabaseError, "taken.db"):
            stepstone.KnowledgeBase.open(out)
        stepstone.KnowledgeBase(width=20, channels=15).save(out, force=True)
        self.assertEqual(len(stepstone.KnowledgeBase.open(out)), 0)

    def test_randomized_and_merged_equal_the_cli(self):
        exported = self.path("kb.db")
        cli("kb", "export", self.run_file, "--out", exported)
        kb = stepstone.KnowledgeBase.open(exported)

        cli("kb", "randomize", exported, "--seed", 7, "--out", self.path("rand.db"))
        rand = kb.randomized(7)
        _, cum, count = stored_kb(self.path("rand.db"))
        np.testing.assert_array_equal(rand.records["average"], cum / count)
        self.assertEqual(rand.randomized_seed, 7)
        np.testing.assert_array_equal(kb.records["average"], stored_kb(exported)[1] / stored_kb(exported)[2],
                                      "randomized() leaves the original as it was")

        other = self.python_kb()
        other.save(self.path("py.db"))
        cli("kb", "merge", exported, self.path("py.db"), "--out", self.path("merged.db"))
        kb.merge(other)
        segments, cum, count = stored_kb(self.path("merged.db"))
        np.testing.assert_array_equal(kb.segments, segments)
        np.testing.assert_array_equal(kb.records["cum_reward"], cum)
        np.testing.assert_array_equal(kb.records["count"], count)
        self.assertEqual([s["run"] for s in kb.sources][-1], "py")
        with self.assertRaisesRegex(stepstone.DataError, "delta"):
            kb.merge(stepstone.KnowledgeBase(width=20, channels=15, delta=2.0))

        coarse = kb.coarsened(3.0)
        cli("kb", "export", self.path("merged.db"), "--delta", 3, "--out", self.path("coarse.db"))
        np.testing.assert_array_equal(coarse.segments, stored_kb(self.path("coarse.db"))[0])


class CountingByPolicy(TempCase):
    """A KB that counts each policy once per KB segment (the paper's footnote 1), made by a run."""

    def test_a_policy_rule_run_kb_is_read_shaped_and_served_alike(self):
        config = dict(TINY_SOURCE, kb=dict(TINY_SOURCE["kb"], counting="policy"))
        run_file = write_run(self.tmp, config, name="policy.db")
        occurrence_file = write_run(self.tmp, TINY_SOURCE, name="occurrence.db")
        kb = stepstone.KnowledgeBase.open(run_file)
        self.assertEqual(kb.counting, "policy")
        self.assertEqual(stepstone.KnowledgeBase.open(occurrence_file).counting, "occurrence")
        stats = cli_json("kb", "stats", run_file, "--json")
        self.assertEqual(stats["counting"], "policy")
        # a source run is not shaped, so both rules see the same policies: the same
        # segments, and by policy never more credits than by occurrence, fewer somewhere
        by_occurrence = stepstone.KnowledgeBase.open(occurrence_file)
        np.testing.assert_array_equal(kb.segments, by_occurrence.segments)
        self.assertTrue((kb.records["count"] <= by_occurrence.records["count"]).all())
        self.assertLess(kb.records["count"].sum(), by_occurrence.records["count"].sum())
        # each policy adds at most one count to a segment: counts never exceed the policies observed
        self.assertLessEqual(kb.records["count"].max(), sum(s["policies"] for s in kb.sources))

        # shape (CLI), serve (HTTP) and the module give one r_max
        served = subprocess.Popen([BINARY, "serve", run_file, "--port", "0"], stdout=subprocess.PIPE, text=True)
        try:
            port = None
            while port is None:
                line = served.stdout.readline()
                self.assertTrue(line, "serve exited before listening")
                found = re.search(r"listening on http://[^:]+:(\d+)", line)
                port = int(found.group(1)) if found else None
            run = stepstone.Run(run_file)
            for individual in run.individuals(generation=4)["id"][:3]:
                mine = kb.lookup(run.replay(int(individual))["behaviour"])
                shaped = cli_json("shape", "--kb", run_file, "--run", run_file, "--individual", int(individual),
                                  "--json")
                self.assertEqual(mine.r_max, shaped["r_max"])
                rows = run.replay(int(individual))["behaviour"].tolist()
                request = urllib.request.Request(f"http://127.0.0.1:{port}/v1/kbs/run/shape",
                                                 data=json.dumps({"behaviour": rows}).encode(),
                                                 headers={"Content-Type": "application/json"})
                with urllib.request.urlopen(request) as answer:
                    self.assertEqual(json.load(answer)["r_max"], mine.r_max)
        finally:
            served.terminate()
            served.wait(10)
            served.stdout.close()

        # KBs of two rules do not merge: one line, no file
        merged = self.path("merged.db")
        result = cli("kb", "merge", run_file, occurrence_file, "--out", merged, "--allow-duplicates", check=False)
        self.assertNotEqual(result.returncode, 0)
        self.assertEqual(len(result.stderr.strip().splitlines()), 1, result.stderr)
        self.assertIn("counts by", result.stderr)
        self.assertFalse(os.path.exists(merged))
        with self.assertRaisesRegex(stepstone.DataError, "counts by policy"):
            kb.merge(by_occurrence)
        with self.assertRaisesRegex(stepstone.ConfigError, "occurrence|policy"):
            stepstone.KnowledgeBase(counting="once")


if __name__ == "__main__":
    unittest.main()
