#include "stats/cox.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/error.hpp"
#include "core/text.hpp"
#include "stats/detail/event_times.hpp"

namespace stepstone::stats {

namespace {

// The quantile of the standard normal distribution at 0.975 (SciPy's norm.ppf(0.975)).
constexpr double kZ95 = 1.959963984540054;
constexpr int kMaxIterations = 100;

using detail::event_times;
using detail::EventTime;

// The log partial likelihood l(beta), its derivative (the score U) and minus its
// second derivative (the information I).
struct Evaluation {
    double loglik = 0, score = 0, information = 0;
};

// With a covariate of 1 in a and 0 in b, an event time with d = d_a + d_b events
// among r_a + r_b subjects at risk contributes
//   d_a beta - sum_{j=0}^{d-1} log(A_j e^beta + B_j)
// to l(beta), where Breslow takes A_j = r_a, B_j = r_b for every j (each tied
// event sees the whole risk set), and Efron A_j = r_a - (j/d) d_a,
// B_j = r_b - (j/d) d_b (the tied events leave the risk set in equal shares).
// Each log term is that of a two-point mixture with weight
// p_j = A_j e^beta / (A_j e^beta + B_j) on a, so the term adds d_a - sum p_j to
// U and sum p_j (1 - p_j) to I. l is concave in beta (I >= 0).
Evaluation evaluate(const std::vector<EventTime>& times, Ties ties, double beta) {
    Evaluation e;
    for (const auto& t : times) {
        const double d = t.events_a + t.events_b;
        e.loglik += t.events_a * beta;
        e.score += t.events_a;
        // Breslow's d terms are equal: one term counted d times
        const int terms = ties == Ties::efron ? static_cast<int>(d) : 1;
        const double multiplicity = ties == Ties::efron ? 1.0 : d;
        for (int j = 0; j < terms; ++j) {
            const double share = ties == Ties::efron ? j / d : 0.0;
            const double weight_a = t.at_risk_a - share * t.events_a;
            const double weight_b = t.at_risk_b - share * t.events_b;
            // log(A e^beta + B) and p without overflow for any beta: through the larger of the two logs
            double log_sum, p;
            if (!(weight_a > 0)) {
                log_sum = std::log(weight_b);
                p = 0;
            } else if (!(weight_b > 0)) {
                log_sum = std::log(weight_a) + beta;
                p = 1;
            } else {
                const double log_a = std::log(weight_a) + beta, log_b = std::log(weight_b);
                log_sum = std::max(log_a, log_b) + std::log1p(std::exp(-std::abs(log_a - log_b)));
                p = 1.0 / (1.0 + std::exp(log_b - log_a));
            }
            e.loglik -= multiplicity * log_sum;
            e.score -= multiplicity * p;
            e.information += multiplicity * p * (1.0 - p);
        }
    }
    return e;
}

}  // namespace

std::string_view to_string(Ties ties) { return ties == Ties::efron ? "efron" : "breslow"; }

std::string_view to_string(CoxStatus status) {
    switch (status) {
        case CoxStatus::estimated:
            return "estimated";
        case CoxStatus::no_events:
            return "no events";
        case CoxStatus::never_together:
            return "never together";
        case CoxStatus::tends_to_zero:
            return "tends to 0";
        case CoxStatus::tends_to_infinity:
            return "tends to infinity";
    }
    return "?";
}

CoxResult cox_hazard_ratio(const Survival& a, const Survival& b, Ties ties) {
    check_survival("cox_hazard_ratio", "a", a);
    check_survival("cox_hazard_ratio", "b", b);
    const std::vector<EventTime> times = event_times(a, b);
    CoxResult result;
    result.ties = ties;

    // U(beta) falls from U(-inf) = (events of a while b is at risk) to
    // U(+inf) = -(events of b while a is at risk): a finite root exists exactly
    // when both are non-zero. Otherwise l keeps rising towards one end.
    bool a_while_b = false, b_while_a = false;
    for (const auto& t : times) {
        result.events_a += static_cast<std::size_t>(t.events_a);
        result.events_b += static_cast<std::size_t>(t.events_b);
        a_while_b = a_while_b || (t.events_a > 0 && t.at_risk_b > 0);
        b_while_a = b_while_a || (t.events_b > 0 && t.at_risk_a > 0);
    }
    const Evaluation at_zero = evaluate(times, ties, 0.0);
    if (at_zero.information > 0) {
        result.score_chi2 = at_zero.score * at_zero.score / at_zero.information;
        result.score_p = chi2_1_sf(result.score_chi2);
    }
    if (times.empty()) {
        result.status = CoxStatus::no_events;
    } else if (!a_while_b && !b_while_a) {
        result.status = CoxStatus::never_together;
    } else if (!a_while_b) {
        result.status = CoxStatus::tends_to_zero;
    } else if (!b_while_a) {
        result.status = CoxStatus::tends_to_infinity;
    } else {
        result.status = CoxStatus::estimated;
    }
    if (result.status != CoxStatus::estimated) return result;

    // Newton-Raphson from beta = 0: beta += U / I. l is strictly concave here
    // (I > 0: some event time has both samples at risk), so the step points
    // uphill; far from the maximum a full step can overshoot, and it is halved
    // until l does not fall (beyond rounding). Stops when a step is below 1e-10
    // relative: the error of Newton's method is then of the order of its square.
    double beta = 0;
    Evaluation current = at_zero;
    for (int iteration = 1; iteration <= kMaxIterations; ++iteration) {
        double step = current.score / current.information;
        Evaluation next = evaluate(times, ties, beta + step);
        const double slack = 1e-12 * std::max(1.0, std::abs(current.loglik));
        for (int halving = 0; halving < 60 && !(next.loglik >= current.loglik - slack); ++halving) {
            step /= 2;
            next = evaluate(times, ties, beta + step);
        }
        beta += step;
        current = next;
        if (std::abs(step) <= 1e-10 * std::max(1.0, std::abs(beta))) {
            HazardRatio hr;
            hr.log_hr = beta;
            hr.se = 1.0 / std::sqrt(current.information);
            hr.hr = std::exp(beta);
            hr.ci_low = std::exp(beta - kZ95 * hr.se);
            hr.ci_high = std::exp(beta + kZ95 * hr.se);
            hr.p = std::erfc(std::abs(beta / hr.se) / std::sqrt(2.0));
            hr.iterations = iteration;
            result.estimate = hr;
            return result;
        }
    }
    // not reached for a concave likelihood with a finite maximum; a bound rather than a hang
    throw DataError(concat("cox_hazard_ratio: Newton-Raphson did not converge in ", kMaxIterations,
                           " steps (beta ", beta, ")"));
}

}  // namespace stepstone::stats
