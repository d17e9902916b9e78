#include "stats/mann_whitney.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>

#include "core/error.hpp"
#include "core/text.hpp"

namespace stepstone::stats {

namespace {

// SciPy's method="auto" uses the exact distribution when a sample has at most
// this many values and the pooled sample has no ties
constexpr std::size_t kExactMaxSize = 8;

void check_sample(const char* function, const char* name, std::span<const double> values) {
    if (values.empty()) throw DataError(concat(function, ": sample ", name, " is empty"));
    for (std::size_t i = 0; i < values.size(); ++i) {
        if (std::isnan(values[i])) {
            throw DataError(concat(function, ": sample ", name, " holds NaN at index ", i));
        }
    }
}

// 2 U_a = 2 #(a_i > b_j) + #(a_i == b_j), exact in integers
std::uint64_t twice_u(std::span<const double> a, std::span<const double> b) {
    std::vector<double> sorted_b(b.begin(), b.end());
    std::sort(sorted_b.begin(), sorted_b.end());
    std::uint64_t twice = 0;
    for (double x : a) {
        const auto [lo, hi] = std::equal_range(sorted_b.begin(), sorted_b.end(), x);
        const auto below = static_cast<std::uint64_t>(lo - sorted_b.begin());
        const auto equal = static_cast<std::uint64_t>(hi - lo);
        twice += 2 * below + equal;
    }
    return twice;
}

}  // namespace

double mann_whitney_exact_cdf(std::size_t n_a, std::size_t n_b, std::size_t k) {
    if (n_a == 0 || n_b == 0) {
        throw DataError(
            concat("mann_whitney_exact_cdf: sample sizes must be positive, got ", n_a, " and ", n_b));
    }
    const std::size_t m = std::min(n_a, n_b);  // inner dimension: the memory is (m + 1) (k + 1)
    const std::size_t n = std::max(n_a, n_b);
    if (k >= m * n) return 1.0;

    // dist[i] = P_{i,j}(0..min(i j, k)): i values of the smaller sample against
    // j of the larger one, j growing from 0 (where U = 0 surely)
    std::vector<std::vector<double>> dist(m + 1, std::vector<double>{1.0});
    for (std::size_t j = 1; j <= n; ++j) {
        // dist[0] stays {1}: no value of the first sample, U = 0
        for (std::size_t i = 1; i <= m; ++i) {
            const double total = static_cast<double>(i + j);
            const double w_first = static_cast<double>(i) / total;   // largest value in the first sample
            const double w_second = static_cast<double>(j) / total;  // largest value in the second
            std::vector<double>& cur = dist[i];                      // P_{i,j-1}, becomes P_{i,j}
            const std::vector<double>& prev = dist[i - 1];           // P_{i-1,j}, already updated
            cur.resize(std::min(i * j, k) + 1, 0.0);
            for (std::size_t u = 0; u < cur.size(); ++u) {
                double value = w_second * cur[u];
                if (u >= j && u - j < prev.size()) value += w_first * prev[u - j];
                cur[u] = value;
            }
        }
    }
    double cdf = 0.0;
    for (double mass : dist[m]) cdf += mass;
    return std::min(cdf, 1.0);
}

MannWhitney mann_whitney_u(std::span<const double> a, std::span<const double> b) {
    check_sample("mann_whitney_u", "a", a);
    check_sample("mann_whitney_u", "b", b);

    const std::size_t n_a = a.size();
    const std::size_t n_b = b.size();
    const std::uint64_t twice_ua = twice_u(a, b);
    const std::uint64_t twice_mn = 2 * static_cast<std::uint64_t>(n_a) * n_b;
    const std::uint64_t twice_larger = std::max(twice_ua, twice_mn - twice_ua);  // 2 max(U_a, U_b)

    MannWhitney result;
    result.u = static_cast<double>(twice_ua) / 2.0;

    // groups of equal values in the pooled sample: sum(t^3 - t)
    std::vector<double> pooled;
    pooled.reserve(n_a + n_b);
    pooled.insert(pooled.end(), a.begin(), a.end());
    pooled.insert(pooled.end(), b.begin(), b.end());
    std::sort(pooled.begin(), pooled.end());
    bool ties = false;
    double tie_term = 0.0;
    for (std::size_t start = 0; start < pooled.size();) {
        std::size_t end = start + 1;
        while (end < pooled.size() && pooled[end] == pooled[start]) ++end;
        if (end - start > 1) {
            ties = true;
            const double t = static_cast<double>(end - start);
            tie_term += t * t * t - t;
        }
        start = end;
    }

    if (std::min(n_a, n_b) <= kExactMaxSize && !ties) {
        // no ties: U is an integer; P(U' >= U) = P(U' <= n_a n_b - U) by symmetry
        result.method = Method::exact;
        const auto lower = static_cast<std::size_t>((twice_mn - twice_larger) / 2);
        result.p = std::min(1.0, 2.0 * mann_whitney_exact_cdf(n_a, n_b, lower));
        return result;
    }

    result.method = Method::asymptotic;
    const double n = static_cast<double>(n_a + n_b);
    const double mn = static_cast<double>(n_a) * static_cast<double>(n_b);
    const double variance = mn / 12.0 * ((n + 1.0) - tie_term / (n * (n - 1.0)));
    const double numerator = static_cast<double>(twice_larger) / 2.0 - mn / 2.0 - 0.5;
    if (variance <= 0.0 || numerator <= 0.0) {
        result.p = 1.0;
        return result;
    }
    const double z = numerator / std::sqrt(variance);
    result.p = std::min(1.0, std::erfc(z / std::sqrt(2.0)));
    return result;
}

double vargha_delaney_a12(std::span<const double> a, std::span<const double> b) {
    check_sample("vargha_delaney_a12", "a", a);
    check_sample("vargha_delaney_a12", "b", b);
    const double mn = static_cast<double>(a.size()) * static_cast<double>(b.size());
    return static_cast<double>(twice_u(a, b)) / 2.0 / mn;
}

std::vector<double> holm(std::span<const double> p) {
    for (std::size_t i = 0; i < p.size(); ++i) {
        if (!(p[i] >= 0.0 && p[i] <= 1.0)) {
            throw DataError(concat("holm: p-value ", i, " is ", p[i], ", not in [0, 1]"));
        }
    }
    const std::size_t m = p.size();
    std::vector<std::size_t> order(m);
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::stable_sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) { return p[x] < p[y]; });

    std::vector<double> adjusted(m);
    double running_max = 0.0;
    for (std::size_t rank = 0; rank < m; ++rank) {
        const double scaled = static_cast<double>(m - rank) * p[order[rank]];
        running_max = std::max(running_max, scaled);
        adjusted[order[rank]] = std::min(1.0, running_max);
    }
    return adjusted;
}

}  // namespace stepstone::stats
