#!/usr/bin/python3
"""Reference values for tests/stats/survival_test.cpp (not run by ctest).

Kaplan-Meier estimates and medians from statsmodels' SurvfuncRight, log-rank
chi2 and p from statsmodels' survdiff (Debian's python3-statsmodels, 0.13.5),
and permutation p-values by enumerating every relabelling with
itertools.combinations. Prints C++ initialisers to paste into the test.

Run: /usr/bin/python3 tests/stats/survival_oracle.py
"""

import itertools

import numpy as np
from statsmodels.duration.survfunc import SurvfuncRight, survdiff

# (name, time a, observed a, time b, observed b): ties, censoring, an arm with no events
FIXTURES = [
    ("ties_and_censoring",
     [3, 5, 5, 8, 10, 10, 12], [1, 1, 0, 1, 0, 1, 0],
     [2, 3, 3, 6, 7, 9, 11, 15], [1, 1, 1, 0, 1, 1, 0, 1]),
    ("no_events_in_a",
     [10, 10, 10, 10], [0, 0, 0, 0],
     [2, 4, 6, 10], [1, 1, 1, 0]),
    ("generations_censored_at_500",
     [0, 0, 12, 40, 500, 500, 500], [1, 1, 1, 1, 0, 0, 0],
     [0, 300, 500, 500, 500, 500, 500], [1, 1, 0, 0, 0, 0, 0]),
]


def median(time, status):
    q = SurvfuncRight(np.array(time, float), np.array(status)).quantile(0.5)
    return "std::nullopt" if np.isnan(q) else repr(float(q))


def survival_steps(time, status):
    sf = SurvfuncRight(np.array(time, float), np.array(status))
    return [(float(t), float(s)) for t, s in zip(sf.surv_times, sf.surv_prob)]


def logrank(ta, sa, tb, sb):
    time = np.array(ta + tb, float)
    status = np.array(sa + sb)
    group = np.array([0] * len(ta) + [1] * len(tb))
    chi2, p = survdiff(time, status, group)
    return float(chi2), float(p)


def mid_ranks(values):
    order = sorted(range(len(values)), key=lambda i: values[i])
    ranks = [0.0] * len(values)
    k = 0
    while k < len(order):
        end = k
        while end < len(order) and values[order[end]] == values[order[k]]:
            end += 1
        for i in range(k, end):
            ranks[order[i]] = (k + 1 + end) / 2
        k = end
    return ranks


def permutation_p(a, b):
    """Two-sided: the share of relabellings whose rank sum of a is as far from its mean."""
    pooled = a + b
    ranks = mid_ranks(pooled)
    n, m = len(pooled), len(a)
    mean = m * (n + 1) / 2
    observed = abs(sum(ranks[:m]) - mean)
    total = extreme = 0
    for chosen in itertools.combinations(range(n), m):
        total += 1
        if abs(sum(ranks[i] for i in chosen) - mean) >= observed - 1e-12:
            extreme += 1
    return extreme, total


PERMUTATIONS = [
    ("hand", [1, 2], [0, 0]),
    ("zeros", [0, 0, 1], [0, 0, 0, 2]),
    ("mostly_ties", [0, 0, 0, 0, 0, 0, 0.25, 0], [0, 0, 0, 0, 0, 0, 0, 0, 0, 0]),
    ("spread", [0.1, 0.4, 0.35, 0.8, 0.5], [0.2, 0.05, 0.3, 0.3, 0.1, 0.0]),
]

if __name__ == "__main__":
    for name, ta, sa, tb, sb in FIXTURES:
        chi2, p = logrank(ta, sa, tb, sb)
        print(f"// {name}")
        print(f"  chi2 = {chi2!r}, p = {p!r}")
        print(f"  median a = {median(ta, sa)}, median b = {median(tb, sb)}")
        print(f"  steps a = {survival_steps(ta, sa)}")
        print(f"  steps b = {survival_steps(tb, sb)}")
    for name, a, b in PERMUTATIONS:
        extreme, total = permutation_p(a, b)
        print(f"// permutation {name}: {extreme} of {total} = {extreme / total!r}")
