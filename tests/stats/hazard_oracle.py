#!/usr/bin/python3
"""Reference values for tests/stats/cox_test.cpp (not run by ctest).

Cox hazard ratios from statsmodels' PHReg (Debian's python3-statsmodels,
0.13.5) with ties="breslow" and ties="efron": params, bse, exp(conf_int()),
pvalues, and the score test at beta = 0 from PHReg.score and PHReg.hessian.
Where the partial likelihood has no finite maximum, PHReg fails to converge
(a ConvergenceWarning, |beta| > 20 and a standard error in the thousands or
more) or raises (no event at all): the script prints which way beta ran
instead of numbers. Restricted mean times (RMST) integrate the step function
of SurvfuncRight's Kaplan-Meier curve with numpy (widths times heights), and
the midpoint median follows R's survfit (its minmin rule) over that curve.
Prints C++ initialisers of the small fixtures to paste into the test, and
writes every hazard ratio and RMST of docs/results/e1_events.csv and
e2_events.csv to tests/stats/hazard_results_expected.csv, which the test reads.

Run: /usr/bin/python3 tests/stats/hazard_oracle.py
"""

import csv
import os
import warnings

import numpy as np
from statsmodels.duration.hazard_regression import PHReg
from statsmodels.duration.survfunc import SurvfuncRight
from statsmodels.tools.sm_exceptions import ConvergenceWarning

HERE = os.path.dirname(os.path.abspath(__file__))
RESULTS = os.path.join(HERE, "..", "..", "docs", "results")

# (name, time a, observed a, time b, observed b, RMST horizon): ties, censoring, arms without events
FIXTURES = [
    ("ties_and_censoring",
     [3, 5, 5, 8, 10, 10, 12], [1, 1, 0, 1, 0, 1, 0],
     [2, 3, 3, 6, 7, 9, 11, 15], [1, 1, 1, 0, 1, 1, 0, 1], 15),
    ("no_events_in_a",
     [10, 10, 10, 10], [0, 0, 0, 0],
     [2, 4, 6, 10], [1, 1, 1, 0], 10),
    ("generations_censored_at_500",
     [0, 0, 12, 40, 500, 500, 500], [1, 1, 1, 1, 0, 0, 0],
     [0, 300, 500, 500, 500, 500, 500], [1, 1, 0, 0, 0, 0, 0], 500),
    ("all_events_tied_at_one_time",
     [5, 5, 5, 8], [1, 1, 1, 0],
     [5, 5, 8, 8], [1, 1, 0, 0], 8),
    ("heavy_ties",
     [1, 1, 2, 2, 2, 3, 4, 4, 6, 6, 6], [1, 1, 1, 0, 1, 1, 1, 0, 1, 0, 0],
     [1, 2, 2, 3, 3, 3, 5, 5, 6, 6], [1, 1, 1, 1, 1, 0, 1, 1, 0, 0], 6),
    ("no_events_in_b",
     [1, 3, 3, 7], [1, 1, 0, 1],
     [2, 5, 9], [0, 0, 0], 9),
    ("no_events_at_all",
     [4, 4], [0, 0],
     [4, 4, 4], [0, 0, 0], 4),
    ("b_events_after_a_left",
     [1, 2, 3], [1, 1, 1],
     [10, 10, 12], [1, 1, 0], 12),
    ("plateau_at_one_half",
     [1, 2, 2, 4], [1, 1, 0, 1],
     [2, 2, 5, 5], [1, 1, 0, 0], 5),
    ("rmst_horizon_inside_the_curve",
     [2, 4, 4, 9, 12], [1, 1, 0, 1, 1],
     [1, 3, 6, 6, 8], [1, 0, 1, 1, 1], 7),
]


def fit(ta, sa, tb, sb, ties):
    """(status, values): values are log_hr, se, hr, ci_low, ci_high, p, score_chi2."""
    time = np.array(ta + tb, float)
    status = np.array(sa + sb)
    x = np.array([1.0] * len(ta) + [0.0] * len(tb))[:, None]
    try:
        model = PHReg(time, x, status=status, ties=ties)
    except IndexError:  # statsmodels cannot build a model without any event
        return "no_events", None
    if status.sum() == 0:
        return "no_events", None
    u = float(model.score(np.zeros(1))[0])
    info = float(-model.hessian(np.zeros(1))[0, 0])
    score = u * u / info if info > 0 else 0.0
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = model.fit()
    diverged = any(issubclass(w.category, ConvergenceWarning) for w in caught)
    beta = float(result.params[0])
    if diverged:
        if abs(beta) < 20 and info > 0:
            raise SystemExit(f"PHReg did not converge at beta {beta}: look at this fixture")
        return ("tends_to_zero" if beta < 0 else "tends_to_infinity"), score
    ci = np.exp(result.conf_int())[0]
    return "estimated", (beta, float(result.bse[0]), float(np.exp(beta)), float(ci[0]), float(ci[1]),
                         float(result.pvalues[0]), score)


def km_curve(time, status):
    sf = SurvfuncRight(np.array(time, float), np.array(status))
    return np.asarray(sf.surv_times, float), np.asarray(sf.surv_prob, float)


def rmst(time, status, horizon):
    """Area under the Kaplan-Meier step function on [0, horizon]."""
    times, prob = km_curve(time, status)
    keep = times <= horizon
    edges = np.concatenate([[0.0], times[keep], [float(horizon)]])
    heights = np.concatenate([[1.0], prob[keep]])
    return float(np.sum(np.diff(edges) * heights))


def median_midpoint(time, status):
    """R survfit's median (print.survfit's minmin): the first time S <= 0.5, the midpoint on a 0.5 plateau."""
    x, y = km_curve(time, status)
    tolerance = np.finfo(float).eps ** 0.5
    keep = y < 0.5 + tolerance
    if not keep.any():
        return None
    x, y = x[keep], y[keep]
    if abs(y[0] - 0.5) < tolerance and (y < y[0]).any():
        return float((x[0] + x[np.argmax(y < y[0])]) / 2)
    return float(x[0])


def cpp(value):
    return "std::nullopt" if value is None else repr(value)


def estimate_text(status, values):
    if status != "estimated":
        return f"CoxStatus::{status}, {{}}"
    return "CoxStatus::estimated, {" + ", ".join(repr(v) for v in values[:6]) + "}"


def print_fixtures():
    print("// fixtures: {name, breslow, efron, score_chi2 breslow, efron, rmst_a, rmst_b, midpoint medians}")
    for name, ta, sa, tb, sb, horizon in FIXTURES:
        print(f"// {name}")
        for ties in ("breslow", "efron"):
            status, values = fit(ta, sa, tb, sb, ties)
            score = values[6] if status == "estimated" else values
            print(f"  {ties}: {estimate_text(status, values)}, score_chi2 {cpp(score)}")
        print(f"  rmst a = {rmst(ta, sa, horizon)!r}, rmst b = {rmst(tb, sb, horizon)!r} (horizon {horizon})")
        print(f"  median_midpoint a = {cpp(median_midpoint(ta, sa))}, b = {cpp(median_midpoint(tb, sb))}")


def read_events(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    treatments = list(dict.fromkeys(r["treatment"] for r in rows))
    events = list(dict.fromkeys(r["event"] for r in rows))
    horizon = max(int(r["generation"]) for r in rows if r["observed"] == "0")
    return rows, treatments, events, horizon


def sample(rows, treatment, event):
    sel = [r for r in rows if r["treatment"] == treatment and r["event"] == event]
    return [int(r["generation"]) for r in sel], [int(r["observed"]) for r in sel]


EXPECTED = os.path.join(HERE, "hazard_results_expected.csv")


def write_results(out, name):
    """Every event and pair of a results events CSV, in the CSV's order (a = 1), both ties methods."""
    rows, treatments, events, horizon = read_events(os.path.join(RESULTS, name))
    for event in events:
        for i, a in enumerate(treatments):
            for b in treatments[i + 1:]:
                ta, sa = sample(rows, a, event)
                tb, sb = sample(rows, b, event)
                # RMST: the numpy integral, and the mean of min(time, horizon) (censoring only at the horizon)
                ra, rb = rmst(ta, sa, horizon), rmst(tb, sb, horizon)
                assert abs(ra - np.mean(np.minimum(ta, horizon))) < 1e-9
                assert abs(rb - np.mean(np.minimum(tb, horizon))) < 1e-9
                for ties in ("breslow", "efron"):
                    status, values = fit(ta, sa, tb, sb, ties)
                    numbers = [repr(v) for v in values[:6]] if status == "estimated" else [""] * 6
                    out.writerow([name, event, a, b, ties, status, *numbers, repr(ra), repr(rb), horizon])


if __name__ == "__main__":
    print_fixtures()
    with open(EXPECTED, "w", newline="") as f:
        out = csv.writer(f, lineterminator="\n")
        out.writerow(["file", "event", "treatment_a", "treatment_b", "ties", "status", "log_hr", "se", "hr",
                      "ci_low", "ci_high", "p_wald", "rmst_a", "rmst_b", "horizon"])
        write_results(out, "e1_events.csv")
        write_results(out, "e2_events.csv")
    print(f"// wrote {os.path.relpath(EXPECTED)}")
