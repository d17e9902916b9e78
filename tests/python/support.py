"""Fixtures of the Python module's tests: the stepstone binary, temporary
folders, and a tiny source run written by `stepstone evolve` (the files the
module must read as the CLI wrote them)."""

import json
import os
import sqlite3
import subprocess
import tempfile
import unittest

import numpy as np

BINARY = os.environ.get("STEPSTONE_BINARY", "stepstone")

# a source run small enough for a test: 1 start of 200 steps (10 segments of 20),
# 8 policies, 4 generations, its KB observed every generation
TINY_SOURCE = {
    "task": {"kind": "source", "steps_per_start": 200, "starts": 1},
    "ea": {"population_size": 8, "generations": 4},
    "kb": {"segment_width": 20, "delta": 1.0, "period": 1},
    "retain": "all",
}


def cli(*args, check=True):
    """Runs the stepstone binary; returns the CompletedProcess (text)."""
    result = subprocess.run([BINARY, *map(str, args)], capture_output=True, text=True)
    if check and result.returncode != 0:
        raise AssertionError(f"stepstone {' '.join(map(str, args))} exited {result.returncode}: {result.stderr}")
    return result


def cli_json(*args):
    return json.loads(cli(*args).stdout)


class TempCase(unittest.TestCase):
    """A test case with a fresh folder, self.tmp, removed afterwards."""

    def setUp(self):
        self._dir = tempfile.TemporaryDirectory(prefix="stepstone-py-")
        self.tmp = self._dir.name

    def tearDown(self):
        self._dir.cleanup()

    def path(self, name):
        return os.path.join(self.tmp, name)


def write_run(folder, config=TINY_SOURCE, seed=1, name="run.db"):
    """Runs `stepstone evolve` on `config`; returns the run file's path."""
    config_path = os.path.join(folder, name + ".json")
    with open(config_path, "w") as f:
        json.dump(config, f)
    db = os.path.join(folder, name)
    cli("evolve", "--config", config_path, "--db", db, "--seed", seed, "--quiet")
    return db


def decode_segment(blob, width, channels):
    """A stored segment as a (width, channels) float32 array, decoded here from
    the format docs/schema.md describes (raw float32, or packed behind 'P')."""
    if len(blob) == width * channels * 4:
        return np.frombuffer(blob, dtype="<f4").reshape(width, channels)
    assert blob[0:1] == b"P", "neither raw nor packed"
    mask_bytes, step_bytes = (channels + 7) // 8, (width + 7) // 8
    binary = [bool(blob[1 + c // 8] >> (c % 8) & 1) for c in range(channels)]
    out = np.zeros((width, channels), dtype=np.float32)
    at = 1 + mask_bytes
    for c in range(channels):
        if binary[c]:
            out[:, c] = [blob[at + r // 8] >> (r % 8) & 1 for r in range(width)]
            at += step_bytes
    for c in range(channels):
        if not binary[c]:
            out[:, c] = np.frombuffer(blob[at:at + 4 * width], dtype="<f4")
            at += 4 * width
    assert at == len(blob)
    return out


def stored_kb(path, name=None):
    """A KB as the file holds it, read with Python's sqlite3 (not the library):
    (segments as a float32 array (n, width, channels), cum_reward, count)."""
    con = sqlite3.connect(f"file:{path}?mode=ro", uri=True)
    try:
        if name is None:
            (kb_id, width, channels), = con.execute("SELECT id, segment_width, channels FROM kb").fetchall()
        else:
            kb_id, width, channels = con.execute(
                "SELECT id, segment_width, channels FROM kb WHERE name = ?", (name,)).fetchone()
        rows = con.execute("SELECT segment_values, cum_reward, count FROM kb_segment WHERE kb_id = ? ORDER BY id",
                           (kb_id,)).fetchall()
    finally:
        con.close()
    segments = np.array([decode_segment(r[0], width, channels) for r in rows]).reshape(len(rows), width, channels)
    return segments, np.array([r[1] for r in rows]), np.array([r[2] for r in rows])
