"""The Python examples run as a user runs them, on files stepstone wrote."""

import os
import subprocess
import sys
import tempfile
import unittest

from support import cli, write_run

EXAMPLES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "examples", "python")


def run_example(name, *args):
    return subprocess.run([sys.executable, os.path.join(EXAMPLES, name), *map(str, args)],
                          capture_output=True, text=True)


class Examples(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls._dir = tempfile.TemporaryDirectory(prefix="stepstone-py-examples-")
        cls.run_file = write_run(cls._dir.name)
        cls.kb = os.path.join(cls._dir.name, "kb.db")
        cli("kb", "export", cls.run_file, "--out", cls.kb)

    @classmethod
    def tearDownClass(cls):
        cls._dir.cleanup()

    def test_shaped_search_checks_r_max_and_searches(self):
        result = run_example("shaped_search.py", "--kb", self.kb, "--run", self.run_file, "--generations", 3,
                             "--population", 4, "--steps", 200)
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertIn("r_max check: ok", result.stdout)
        self.assertEqual(result.stdout.count("generation "), 3)
        self.assertIn("best fitness", result.stdout)

    def test_shaped_search_refuses_a_missing_kb(self):
        result = run_example("shaped_search.py", "--kb", os.path.join(self._dir.name, "none.db"), "--run", self.run_file)
        self.assertEqual(result.returncode, 1)
        self.assertEqual(result.stderr.strip().count("\n"), 0, "one line")
        self.assertIn("none.db: no such file", result.stderr)

    def test_lookup_speed_reports_both_rates(self):
        # a small KB and few policies: checks that it runs and reports, not how fast (that is bench's job)
        result = run_example("lookup_speed.py", "--source-policies", 10, "--policies", 3, "--repeats", 1)
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertEqual(result.stdout.count("ratio"), 2, result.stdout)


if __name__ == "__main__":
    unittest.main()
