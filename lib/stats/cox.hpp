#pragma once

// The Cox proportional-hazards model of two samples: one binary covariate,
// the hazard ratio of the first sample to the second (docs/statistics.md).

#include <cstddef>
#include <optional>
#include <string_view>

#include "stats/survival.hpp"

namespace stepstone::stats {

/// How the partial likelihood treats events at the same time.
enum class Ties {
    breslow,  ///< every tied event sees the whole risk set (statsmodels' PHReg default)
    efron,    ///< the tied events leave the risk set in equal shares (R's coxph default)
};
/// "breslow", "efron".
std::string_view to_string(Ties ties);

/// Whether the partial likelihood has a finite maximum, and why not.
enum class CoxStatus {
    estimated,          ///< a finite maximum: `CoxResult::estimate` holds it
    no_events,          ///< no event in either sample: nothing to estimate
    never_together,     ///< no event time with both samples at risk: the likelihood is flat
    tends_to_zero,      ///< no event of a while b is at risk (e.g. a has none): the MLE of the HR is 0
    tends_to_infinity,  ///< no event of b while a is at risk (e.g. b has none): the MLE is +infinity
};
/// "estimated", "no events", "never together", "tends to 0", "tends to infinity".
std::string_view to_string(CoxStatus status);

/// The maximum partial-likelihood estimate and its Wald statistics.
struct HazardRatio {
    double log_hr = 0;   ///< beta: the log hazard ratio of a to b
    double se = 0;       ///< 1 / sqrt(information at beta), the observed information
    double hr = 1;       ///< exp(beta)
    double ci_low = 1;   ///< exp(beta - z se), z = 1.959963984540054 (95 %)
    double ci_high = 1;  ///< exp(beta + z se)
    double p = 1;        ///< Wald p: P(|N(0, 1)| >= |beta / se|)
    int iterations = 0;  ///< Newton-Raphson steps taken
};

/// A two-sample Cox model: the first sample has covariate 1, the second 0.
struct CoxResult {
    std::size_t events_a = 0, events_b = 0;
    Ties ties = Ties::efron;
    CoxStatus status = CoxStatus::no_events;
    /// Present exactly when status is `estimated`.
    std::optional<HazardRatio> estimate;
    /// The score (Rao) test of beta = 0: U(0)^2 / I(0), and its chi-square
    /// (1 df) p; 0 and 1 when I(0) is 0 (no event time with both samples at
    /// risk). Defined whether or not the estimate is.
    double score_chi2 = 0, score_p = 1;
};

/// The hazard ratio of sample `a` to sample `b` in the Cox proportional-hazards
/// model with one binary covariate (1 in a, 0 in b), the maximum of the partial
/// likelihood found by Newton-Raphson from beta = 0, with step halving. The
/// numbers are those of statsmodels' PHReg(time, covariate, status,
/// ties=...).fit(): params, bse and conf_int. When the likelihood has no finite
/// maximum (status not `estimated`, see CoxStatus) there is no estimate: never
/// a NaN or a huge beta. Throws DataError as kaplan_meier does for either sample.
CoxResult cox_hazard_ratio(const Survival& a, const Survival& b, Ties ties = Ties::efron);

}  // namespace stepstone::stats
