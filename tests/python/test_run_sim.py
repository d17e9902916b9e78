"""stepstone.Run, Task, Episode and evaluate against what the stepstone CLI
wrote: a run's stored rows and rewards (read with Python's sqlite3) and the
per-step CSV of `stepstone simulate`."""

import csv
import json
import os
import pathlib
import sqlite3
import tempfile
import unittest

import numpy as np

import stepstone
from support import TempCase, cli, write_run

INPUTS = ["laser_p45", "laser_m45", "laser_0", "ball_p45", "ball_m45", "basket_p45", "basket_m45",
          "switch_p45", "switch_m45", "bumper_left", "bumper_right", "carrying"]
OUTPUTS = ["left_wheel", "right_wheel", "action"]


class Simulator(TempCase):
    def test_a_python_driven_episode_steps_as_stepstone_simulate(self):
        # the CLI's random controller, its outputs fed back from Python: the same inputs and poses
        csv_path = self.path("steps.csv")
        cli("simulate", "--task", "target", "--controller", "random", "--seed", 5, "--steps", 300, "--starts", 2,
            "--csv", csv_path)
        with open(csv_path) as f:
            rows = list(csv.DictReader(f))
        self.assertEqual(len(rows), 600)
        episode = stepstone.Episode(stepstone.Task("target", steps_per_start=300, starts=2))
        observation, done = episode.observation, False
        for k, row in enumerate(rows):
            self.assertFalse(done, f"the episode ended early at row {k}")
            self.assertEqual(episode.start, int(row["start"]) - 1)
            np.testing.assert_array_equal(observation, np.array([row[c] for c in INPUTS], dtype=np.float32),
                                          f"inputs of row {k}")
            self.assertEqual(episode.pose, (float(row["x"]), float(row["y"]), float(row["heading"])))
            observation, done = episode.step(np.array([row[c] for c in OUTPUTS], dtype=np.float32))
            self.assertEqual(episode.balls, int(row["balls"]))
        self.assertTrue(done)
        result = episode.finish()
        self.assertEqual(result["steps"], 600)
        self.assertEqual(result["behaviour"].shape, (300, 15))
        np.testing.assert_array_equal(result["behaviour"][:, 12:],
                                      np.array([[r[c] for c in OUTPUTS] for r in rows[:300]], dtype=np.float32))
        with self.assertRaisesRegex(ValueError, "the episode is over"):
            episode.step([0, 0, 0])

    def test_an_arena_from_a_file_or_a_dict(self):
        here = os.path.dirname(os.path.abspath(__file__))
        path = os.path.join(here, "..", "..", "examples", "arenas", "two_rooms.json")
        by_file = stepstone.Task("target", steps_per_start=200, starts=1, arena=path)
        with open(path) as f:
            arena = json.load(f)
        self.assertEqual(by_file.arena["target_ball"], 5)
        self.assertEqual(by_file.arena["walls"][6]["box"], [430, 120, 470, 200])
        by_dict = stepstone.Task("target", steps_per_start=200, starts=1, arena=arena)
        genome = stepstone.random_genome(4)
        a, b = stepstone.evaluate(by_file, genome), stepstone.evaluate(by_dict, genome)
        np.testing.assert_array_equal(a["behaviour"], b["behaviour"])
        paper = stepstone.evaluate(stepstone.Task("target", steps_per_start=200, starts=1), genome)
        self.assertFalse(np.array_equal(a["behaviour"], paper["behaviour"]), "another arena, other sensor values")
        self.assertEqual(stepstone.Task().arena, stepstone.paper_arena())
        arena["starts"][0] = [440, 205, 0]
        with self.assertRaisesRegex(stepstone.ConfigError, r"starts\[0\]: .* inside the wall 'pillar'"):
            stepstone.Task(arena=arena)

    def test_bad_input(self):
        episode = stepstone.Episode(stepstone.Task("source", steps_per_start=10, starts=1))
        with self.assertRaisesRegex(ValueError, "outputs must hold 3 values"):
            episode.step([0.5, 0.5])
        with self.assertRaisesRegex(stepstone.ConfigError, "starts"):
            stepstone.Task("source", starts=4)
        with self.assertRaisesRegex(stepstone.DataError, "genome"):
            stepstone.evaluate(stepstone.Task(), {"inputs": 12})
        with self.assertRaisesRegex(stepstone.DataError, "not JSON"):
            stepstone.evaluate(stepstone.Task(), "{not json")

    def test_a_still_robot_ends_the_episode(self):
        # the stand-still rule: more than still_limit still steps end every start
        task = stepstone.Task("source", steps_per_start=500, starts=3, still_limit=20)
        episode = stepstone.Episode(task)
        steps, done = 0, False
        while not done:
            _, done = episode.step([0.5, 0.5, 0.0])  # both wheels at 0.5: no motion
            steps += 1
        result = episode.finish()
        self.assertTrue(result["stopped_early"])
        self.assertEqual(result["steps"], steps)
        self.assertLess(steps, 500)


class Runs(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls._dir = tempfile.TemporaryDirectory(prefix="stepstone-py-run-")
        cls.path = write_run(cls._dir.name)
        cls.stored = stepstone.Run(cls.path)
        cls.sql = sqlite3.connect(f"file:{cls.path}?mode=ro", uri=True)

    @classmethod
    def tearDownClass(cls):
        cls.sql.close()
        cls._dir.cleanup()

    def test_paths_may_be_pathlib_paths(self):
        path = pathlib.Path(self.path)
        self.assertEqual(stepstone.Run(path).seed, self.stored.seed)
        kb = stepstone.KnowledgeBase.open(path)
        with tempfile.TemporaryDirectory() as folder:
            kb.save(pathlib.Path(folder) / "kb.db")
            self.assertEqual(len(stepstone.KnowledgeBase.open(pathlib.Path(folder) / "kb.db")), len(kb))
        here = pathlib.Path(__file__).resolve().parent
        arena = here.parent.parent / "examples" / "arenas" / "two_rooms.json"
        self.assertEqual(stepstone.Task("target", arena=arena).arena["target_ball"], 5)
        with self.assertRaises(stepstone.DatabaseError):
            stepstone.Run(pathlib.Path(folder) / "missing.db")

    def test_the_run_row(self):
        run = self.stored
        self.assertEqual((run.task, run.treatment, run.seed, run.status), ("source", "none", 1, "finished"))
        self.assertEqual((run.generations_asked, run.generations_done), (4, 4))
        self.assertEqual(run.config["task"]["steps_per_start"], 200)

    def test_individuals_and_generations_are_the_stored_rows(self):
        rows = self.sql.execute("SELECT id, generation, parent_id, reward, balls, steps, presses, carry_steps "
                                "FROM individual ORDER BY id").fetchall()
        table = self.stored.individuals()
        self.assertEqual(len(table), len(rows))
        np.testing.assert_array_equal(table["id"], [r[0] for r in rows])
        np.testing.assert_array_equal(table["parent_id"], [-1 if r[2] is None else r[2] for r in rows])
        np.testing.assert_array_equal(table["reward"], [r[3] for r in rows])
        np.testing.assert_array_equal(table["steps"], [r[5] for r in rows])
        np.testing.assert_array_equal(table["presses"], [r[6] for r in rows])
        self.assertTrue(np.isnan(table["r_max"]).all(), "a run without a KB shapes nothing")
        third = self.stored.individuals(generation=3)
        np.testing.assert_array_equal(third["id"], [r[0] for r in rows if r[1] == 3])
        generations = self.stored.generations()
        np.testing.assert_array_equal(generations["generation"], [0, 1, 2, 3, 4])
        np.testing.assert_array_equal(generations["best_reward"], [r[0] for r in self.sql.execute(
            "SELECT best_reward FROM generation ORDER BY generation")])
        frame = self.stored.individuals_frame()
        self.assertEqual(list(frame.columns), list(table.dtype.names))
        self.assertEqual(len(self.stored.generations_frame()), 5)

    def test_stored_genomes_evaluate_to_their_stored_rewards(self):
        task = stepstone.Task(**self.stored.config["task"], math=self.stored.config.get("math", "libm"))
        rows = self.sql.execute("SELECT g.individual_id, i.reward, i.balls, i.steps FROM genome g "
                                "JOIN individual i ON i.id = g.individual_id WHERE i.generation = 3").fetchall()
        self.assertGreater(len(rows), 0)
        for individual, reward, balls, steps in rows:
            result = stepstone.evaluate(task, self.stored.genome(individual), dnn=self.stored.config["dnn"])
            self.assertEqual((result["reward"], result["balls"], result["steps"]), (reward, balls, steps))
            replayed = self.stored.replay(individual)
            self.assertEqual(replayed["reward"], reward)
            np.testing.assert_array_equal(replayed["behaviour"], result["behaviour"])
        best_reward = self.sql.execute("SELECT max(i.reward) FROM genome g JOIN individual i "
                                       "ON i.id = g.individual_id").fetchone()[0]
        self.assertEqual(self.stored.replay("best")["stored_reward"], best_reward)

    def test_a_seeded_run_shows_its_source(self):
        self.assertIsNone(self.stored.seeded_from)
        with tempfile.TemporaryDirectory() as folder:
            config = folder + "/t.json"
            with open(config, "w") as out:
                json.dump({"task": {"kind": "target", "steps_per_start": 200, "starts": 1},
                           "ea": {"population_size": 8, "generations": 1}, "seed": 2}, out)
            target = folder + "/seeded.db"
            cli("evolve", "--config", config, "--db", target, "--seed-from", self.path, "--seed-with", "best",
                "--seed-count", "3", "--quiet")
            run = stepstone.Run(target)
            self.assertEqual(run.treatment, "seed")
            digest = cli("db", "digest", self.path).stdout.strip()
            expected = {"from": os.path.abspath(self.path), "with": "best", "count": 3, "digest": digest}
            self.assertEqual(run.seeded_from, expected)
            self.assertEqual(run.config["transfer"]["seed"], expected)
            # generation 0 starts with the source's best stored genome
            best = self.sql.execute("SELECT g.individual_id FROM genome g JOIN individual i "
                                    "ON i.id = g.individual_id ORDER BY i.reward DESC, i.id LIMIT 1").fetchone()[0]
            self.assertEqual(run.genome(0), self.stored.genome(best))

    def test_errors_name_the_file(self):
        with tempfile.TemporaryDirectory() as folder:
            kb_file = folder + "/kb.db"
            cli("kb", "export", self.path, "--out", kb_file)
            with self.assertRaisesRegex(stepstone.DatabaseError, "kb.db"):
                stepstone.Run(kb_file)
        with self.assertRaisesRegex(stepstone.DataError, "999999"):
            self.stored.genome(999999)
        with self.assertRaises(TypeError):
            self.stored.replay(2.5)
        with self.assertRaisesRegex(stepstone.ConfigError, "^individual must be 'best' or an individual id"):
            self.stored.replay("worst")


class Docs(unittest.TestCase):
    def test_every_public_name_has_a_docstring(self):
        import inspect
        missing = []
        for name, obj in vars(stepstone).items():
            if name.startswith("__"):
                continue
            if not (obj.__doc__ or "").strip():
                missing.append(name)
            if inspect.isclass(obj):
                for attribute, value in vars(obj).items():
                    if attribute.startswith("_") and attribute not in ("__init__", "__len__"):
                        continue
                    if not (getattr(value, "__doc__", None) or "").strip():
                        missing.append(f"{name}.{attribute}")
        self.assertEqual(missing, [])


if __name__ == "__main__":
    unittest.main()
