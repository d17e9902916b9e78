#pragma once

// The risk sets of two right-censored samples, shared by the log-rank test and
// the Cox model (survival.cpp, cox.cpp).

#include <algorithm>
#include <cstddef>
#include <vector>

#include "stats/survival.hpp"

namespace stepstone::stats::detail {

/// One distinct time at which at least one event happened: the subjects of each
/// sample still followed then (at risk: time >= t) and those whose event it is.
struct EventTime {
    double at_risk_a = 0, at_risk_b = 0;
    double events_a = 0, events_b = 0;
};

/// The event times of the pooled samples, ascending; censored-only times are
/// left out (they only shrink the later risk sets). Counts are whole numbers
/// held in doubles, exact up to 2^53.
inline std::vector<EventTime> event_times(const Survival& a, const Survival& b) {
    struct Entry {
        double time;
        bool first;
        bool observed;
    };
    std::vector<Entry> pooled;
    pooled.reserve(a.time.size() + b.time.size());
    for (std::size_t i = 0; i < a.time.size(); ++i) pooled.push_back({a.time[i], true, a.observed[i] == 1});
    for (std::size_t i = 0; i < b.time.size(); ++i) pooled.push_back({b.time[i], false, b.observed[i] == 1});
    std::stable_sort(pooled.begin(), pooled.end(),
                     [](const Entry& x, const Entry& y) { return x.time < y.time; });
    std::vector<EventTime> times;
    double n_a = static_cast<double>(a.time.size());
    double n_b = static_cast<double>(b.time.size());
    for (std::size_t k = 0; k < pooled.size();) {
        const double t = pooled[k].time;
        EventTime here{n_a, n_b, 0, 0};
        for (; k < pooled.size() && pooled[k].time == t; ++k) {
            (pooled[k].first ? n_a : n_b) -= 1;
            if (pooled[k].observed) (pooled[k].first ? here.events_a : here.events_b) += 1;
        }
        if (here.events_a + here.events_b > 0) times.push_back(here);
    }
    return times;
}

}  // namespace stepstone::stats::detail
