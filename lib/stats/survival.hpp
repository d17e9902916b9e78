#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <vector>

namespace stepstone::stats {

/// Right-censored times to event: time[i] with observed[i] 1 when the event
/// happened at time[i], 0 when the subject was followed up to time[i]
/// without it (censored). Times are any finite doubles (here: generations).
struct Survival {
    std::vector<double> time;
    std::vector<int> observed;
};

/// One step of a Kaplan-Meier curve: at `time`, `events` of the `at_risk`
/// subjects still followed had the event, `censored` left the study, and the
/// estimate after the step is `survival`.
struct KaplanMeierStep {
    double time = 0;
    std::size_t at_risk = 0;
    std::size_t events = 0;
    std::size_t censored = 0;
    double survival = 1;
};

/// The Kaplan-Meier estimate of a sample.
struct KaplanMeier {
    std::size_t n = 0;
    std::size_t events = 0;
    /// One step per distinct time (events or censoring), ascending. Subjects
    /// censored at an event time are at risk at that time (the usual convention).
    std::vector<KaplanMeierStep> steps;
    /// Median time to event, strict convention: the first event time at which
    /// the estimate falls strictly below 0.5 (statsmodels'
    /// SurvfuncRight.quantile(0.5)); absent ("not reached") when it never does.
    std::optional<double> median;
    /// Median time to event, midpoint convention (R's survfit and SAS's
    /// LIFETEST): the first event time t_i with S(t_i) <= 0.5, except where S
    /// sits at exactly 0.5 from t_i until the next event time t_j, which gives
    /// (t_i + t_j) / 2. When S stays at 0.5 to the end of the curve, survfit
    /// gives t_i, and so does this. Differs from `median` only on such a
    /// plateau; absent when S never reaches 0.5. ("Exactly" is within 1e-12,
    /// as products like 3/4 * 2/3 are 0.5 only up to rounding.)
    std::optional<double> median_midpoint;

    /// The estimate S(t): the survival after the last step at or before t (1 before the first).
    double at(double t) const;
    /// Subjects at risk just before t: followed up to t or later.
    std::size_t at_risk(double t) const;
};

/// Kaplan-Meier product-limit estimate: S(t) = prod over event times t_i <= t
/// of (1 - d_i / n_i). Throws DataError when the sample is empty, the vectors
/// differ in size, a time is not finite or an observed flag is not 0 or 1.
KaplanMeier kaplan_meier(const Survival& sample);

/// The restricted mean time to event up to `horizon` (RMST): the area under
/// the Kaplan-Meier curve from 0 to `horizon`, the integral of the step
/// function S(t) as `KaplanMeier::at` gives it. With every subject followed up
/// to `horizon` or to its event, it is the mean of min(time, horizon). Throws
/// DataError for a negative or non-finite horizon.
double restricted_mean(const KaplanMeier& km, double horizon);

/// Throws DataError naming `function` and the sample `name` when `sample` is
/// empty, its vectors differ in size, a time is not finite or an observed flag
/// is not 0 or 1 (the checks of kaplan_meier and log_rank).
void check_survival(const char* function, const char* name, const Survival& sample);

/// The result of a two-sample log-rank test.
struct LogRank {
    std::size_t events_a = 0, events_b = 0;
    double expected_a = 0;  ///< events expected in the first sample under the null
    double variance = 0;    ///< hypergeometric variance of observed_a - expected_a
    double chi2 = 0;        ///< (events_a - expected_a)^2 / variance; 0 when the variance is 0
    double p = 1;           ///< P(chi-square with 1 df >= chi2); 1 when no event happened
};

/// The (unweighted) log-rank test of two right-censored samples, as
/// statsmodels' survdiff(time, status, group) computes it: at every distinct
/// event time t with d events among n at risk (n_a in the first sample),
/// E_a += d n_a / n and V += d (n_a / n) (1 - n_a / n) (n - d) / (n - 1).
/// Throws DataError as kaplan_meier does for either sample.
LogRank log_rank(const Survival& a, const Survival& b);

/// The two-sided permutation p of a two-sample rank comparison (the
/// Mann-Whitney U test with ties), and how it was obtained.
struct PermutationP {
    double p = 1;
    bool exact = true;          ///< every relabelling counted; false: Monte Carlo
    std::size_t draws = 0;      ///< Monte Carlo relabellings (0 when exact)
    double standard_error = 0;  ///< of the Monte Carlo p (0 when exact)
};

/// The exact permutation p of the Mann-Whitney U statistic under every one of
/// the C(n_a + n_b, n_a) relabellings of the pooled sample, ties kept as
/// mid-ranks: p = P(|R' - E R| >= |R - E R|), R the sum of the first
/// sample's mid-ranks, R' its value under a uniformly drawn relabelling.
/// The relabellings are counted by their rank sum (a dynamic programme over
/// the pooled values, exact in double up to ~1e15 relabellings and accurate
/// to a few ulps beyond); past `exact_limit` operations of that programme, p
/// comes from `draws` relabellings drawn with `seed` (Monte Carlo, the
/// observed one included: p = (1 + hits) / (1 + draws)), with its standard
/// error. Throws DataError for an empty sample or a NaN.
PermutationP permutation_p(std::span<const double> a, std::span<const double> b,
                           std::size_t exact_limit = 200000000, std::size_t draws = 100000,
                           unsigned long long seed = 1);

/// The share of the pooled sample that lies in groups of equal values (0 when
/// every value is distinct, 1 when none is). Throws DataError for an empty pooled sample.
double tied_share(std::span<const double> a, std::span<const double> b);

/// The upper tail of the chi-square distribution with one degree of freedom: erfc(sqrt(x / 2)).
double chi2_1_sf(double x);

}  // namespace stepstone::stats
