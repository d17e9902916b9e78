#include "stats/summary.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/error.hpp"
#include "core/text.hpp"

namespace stepstone::stats {

namespace {

// type-7 quantile of sorted, non-empty values, in R's arithmetic
double quantile7(const std::vector<double>& sorted, double q) {
    const double h = static_cast<double>(sorted.size() - 1) * q;
    const double floor_h = std::floor(h);
    const auto lo = static_cast<std::size_t>(floor_h);
    const double f = h - floor_h;
    if (f == 0.0 || lo + 1 >= sorted.size() || sorted[lo + 1] == sorted[lo]) return sorted[lo];
    return (1.0 - f) * sorted[lo] + f * sorted[lo + 1];
}

// the values sorted; throws for none or a NaN, naming `what`
std::vector<double> sorted_sample(std::span<const double> values, const char* what) {
    if (values.empty()) throw DataError(concat(what, ": no values"));
    for (std::size_t i = 0; i < values.size(); ++i) {
        if (std::isnan(values[i])) throw DataError(concat(what, ": value ", i, " is NaN"));
    }
    std::vector<double> sorted(values.begin(), values.end());
    std::sort(sorted.begin(), sorted.end());
    return sorted;
}

}  // namespace

double median(std::span<const double> values) { return quantile7(sorted_sample(values, "median"), 0.5); }

Summary summarize(std::span<const double> values) {
    const std::vector<double> sorted = sorted_sample(values, "summarize");

    double sum = 0.0;
    for (double x : values) sum += x;

    Summary s;
    s.n = values.size();
    s.min = sorted.front();
    s.q1 = quantile7(sorted, 0.25);
    s.median = quantile7(sorted, 0.5);
    s.q3 = quantile7(sorted, 0.75);
    s.max = sorted.back();
    s.mean = sum / static_cast<double>(s.n);
    return s;
}

std::size_t count_at_least(std::span<const double> values, double threshold) {
    if (std::isnan(threshold)) throw DataError("count_at_least: the threshold is NaN");
    std::size_t count = 0;
    for (std::size_t i = 0; i < values.size(); ++i) {
        if (std::isnan(values[i])) throw DataError(concat("count_at_least: value ", i, " is NaN"));
        if (values[i] >= threshold) ++count;
    }
    return count;
}

}  // namespace stepstone::stats
