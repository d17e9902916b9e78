#include "stats/survival.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "core/error.hpp"
#include "core/text.hpp"
#include "stats/detail/event_times.hpp"

namespace stepstone::stats {

void check_survival(const char* function, const char* name, const Survival& s) {
    if (s.time.empty()) throw DataError(concat(function, ": sample ", name, " is empty"));
    if (s.time.size() != s.observed.size()) {
        throw DataError(concat(function, ": sample ", name, " has ", s.time.size(), " times and ",
                               s.observed.size(), " observed flags"));
    }
    for (std::size_t i = 0; i < s.time.size(); ++i) {
        if (!std::isfinite(s.time[i]))
            throw DataError(concat(function, ": sample ", name, " time ", i, " is not finite"));
        if (s.observed[i] != 0 && s.observed[i] != 1) {
            throw DataError(concat(function, ": sample ", name, " observed flag ", i, " is ", s.observed[i],
                                   ", not 0 or 1"));
        }
    }
}

namespace {

// indices of the sample sorted by time
std::vector<std::size_t> by_time(const Survival& s) {
    std::vector<std::size_t> order(s.time.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t i, std::size_t j) { return s.time[i] < s.time[j]; });
    return order;
}

}  // namespace

double KaplanMeier::at(double t) const {
    double s = 1.0;
    for (const auto& step : steps) {
        if (step.time > t) break;
        s = step.survival;
    }
    return s;
}

std::size_t KaplanMeier::at_risk(double t) const {
    for (const auto& step : steps) {
        if (step.time >= t) return step.at_risk;
    }
    return 0;
}

KaplanMeier kaplan_meier(const Survival& sample) {
    check_survival("kaplan_meier", "", sample);
    KaplanMeier km;
    km.n = sample.time.size();
    const auto order = by_time(sample);
    std::size_t at_risk = km.n;
    double survival = 1.0;
    bool plateau = false;  // S is 0.5 (within rounding) since the midpoint median's first time
    for (std::size_t k = 0; k < order.size();) {
        KaplanMeierStep step;
        step.time = sample.time[order[k]];
        step.at_risk = at_risk;
        for (; k < order.size() && sample.time[order[k]] == step.time; ++k) {
            (sample.observed[order[k]] ? step.events : step.censored) += 1;
        }
        if (step.events > 0) {
            survival *= 1.0 - static_cast<double>(step.events) / static_cast<double>(step.at_risk);
        }
        step.survival = survival;
        // strictly below one half in exact arithmetic: an estimate that is 0.5 up to rounding is not below it
        if (!km.median && step.events > 0 && survival < 0.5 - 1e-12) km.median = step.time;
        // R's survfit: the first time S <= 0.5; on a plateau at 0.5, the midpoint to the next drop
        if (!km.median_midpoint && step.events > 0 && survival < 0.5 + 1e-12) {
            km.median_midpoint = step.time;
            plateau = survival > 0.5 - 1e-12;
        } else if (plateau && step.events > 0) {
            km.median_midpoint = (*km.median_midpoint + step.time) / 2.0;
            plateau = false;
        }
        km.events += step.events;
        at_risk -= step.events + step.censored;
        km.steps.push_back(step);
    }
    return km;
}

double restricted_mean(const KaplanMeier& km, double horizon) {
    if (!(std::isfinite(horizon) && horizon >= 0)) {
        throw DataError(concat("restricted_mean: the horizon must be finite and >= 0, got ", horizon));
    }
    // S is a right-continuous step function: s on [from, next step), the steps at or before 0 give S(0)
    double area = 0, from = 0, s = 1.0;
    for (const auto& step : km.steps) {
        if (step.time > horizon) break;
        if (step.time > from) {
            area += s * (step.time - from);
            from = step.time;
        }
        s = step.survival;
    }
    return area + s * (horizon - from);
}

double chi2_1_sf(double x) {
    if (!(x > 0)) return 1.0;
    return std::erfc(std::sqrt(x / 2.0));
}

LogRank log_rank(const Survival& a, const Survival& b) {
    check_survival("log_rank", "a", a);
    check_survival("log_rank", "b", b);
    // the distinct event times in order, with each sample's risk set
    LogRank result;
    for (const auto& t : detail::event_times(a, b)) {
        const double n = t.at_risk_a + t.at_risk_b;
        const double d = t.events_a + t.events_b;
        const double share = t.at_risk_a / n;
        result.expected_a += d * share;
        if (n > 1) result.variance += d * share * (1.0 - share) * (n - d) / (n - 1.0);
        result.events_a += static_cast<std::size_t>(t.events_a);
        result.events_b += static_cast<std::size_t>(t.events_b);
    }
    const double diff = static_cast<double>(result.events_a) - result.expected_a;
    result.chi2 = result.variance > 0 ? diff * diff / result.variance : 0.0;
    result.p = result.variance > 0 ? chi2_1_sf(result.chi2) : 1.0;
    return result;
}

}  // namespace stepstone::stats
