#!/usr/bin/python3
"""docs/results/l_reading.py, L's registered reading rule, applied to E1's and E2's committed
CSVs: it must give the hazard ratios and CIs recorded in docs/results.md section 9 (statsmodels'
PHReg, checked by scripts/hazard-check), pick the rule's branch a reader picks by hand from
them, and print nothing but the run counts while an arm is short of the runs asked.
Usage: reading_rule_test.py L_READING.py"""
import subprocess
import sys


def run(script, *args):
    out = subprocess.run(["/usr/bin/python3", script, *args], capture_output=True, text=True)
    if out.returncode != 0:
        sys.exit(f"reading_rule_test: {' '.join(args)} exited {out.returncode}: {out.stderr.strip()}")
    return out.stdout


def expect(text, wanted, label):
    if wanted not in text:
        sys.exit(f"reading_rule_test: {label}: expected {wanted!r} in:\n{text}")


def main():
    script = sys.argv[1]
    # E2, first pickup: HR 1.18 (0.61-2.27), p = 0.63; the upper bound is below 3
    e2 = run(script, "--prefix", "e2", "--event", "pickup", "--runs", "20")
    expect(e2, "hazard ratio sum to none: 1.18 (95 % CI 0.608-2.27)", "E2")
    expect(e2, "p 0.6257", "E2")
    expect(e2, "rule: a paper-sized effect refuted", "E2")
    # E1, first release: HR 1.34 (0.30-6.0), p = 0.70; the upper bound is above 3
    e1 = run(script, "--prefix", "e1", "--event", "release", "--runs", "20")
    expect(e1, "hazard ratio sum to none: 1.34 (95 % CI 0.3-6)", "E1")
    expect(e1, "rule: inconclusive", "E1")
    # E4's arms are none / seed / sum: none vs sum on the first ball has no event in either arm
    e4 = run(script, "--prefix", "e4", "--event", "ball", "--runs", "20")
    expect(e4, "not estimable", "E4")
    expect(e4, "rule: inconclusive", "E4")
    # an arm short of the runs asked: counts only
    short = run(script, "--prefix", "e2", "--event", "pickup", "--runs", "21")
    expect(short, "interim: not read", "interim")
    if "hazard" in short or "rule:" in short:
        sys.exit(f"reading_rule_test: an interim reading printed results:\n{short}")
    print("reading_rule_test: E1's and E2's recorded hazard ratios and branches, and the interim guard")


if __name__ == "__main__":
    main()
