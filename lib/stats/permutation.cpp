// The permutation p of the Mann-Whitney comparison (stats/survival.hpp):
// exact by counting relabellings per rank sum, or Monte Carlo past a size.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <random>

#include "core/error.hpp"
#include "core/text.hpp"
#include "stats/survival.hpp"

namespace stepstone::stats {

namespace {

void check_values(const char* name, std::span<const double> values) {
    if (values.empty()) throw DataError(concat("permutation_p: sample ", name, " is empty"));
    for (std::size_t i = 0; i < values.size(); ++i) {
        if (std::isnan(values[i]))
            throw DataError(concat("permutation_p: sample ", name, " holds NaN at index ", i));
    }
}

// twice the mid-rank of every pooled value (integers), in pooled order a then b
std::vector<std::int64_t> doubled_mid_ranks(std::span<const double> a, std::span<const double> b) {
    std::vector<double> pooled(a.begin(), a.end());
    pooled.insert(pooled.end(), b.begin(), b.end());
    std::vector<std::size_t> order(pooled.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t i, std::size_t j) { return pooled[i] < pooled[j]; });
    std::vector<std::int64_t> ranks(pooled.size());
    for (std::size_t k = 0; k < order.size();) {
        std::size_t end = k;
        while (end < order.size() && pooled[order[end]] == pooled[order[k]]) ++end;
        // ranks k + 1 .. end share their mean (k + 1 + end) / 2
        const auto twice_mid = static_cast<std::int64_t>(k + 1 + end);
        for (std::size_t i = k; i < end; ++i) ranks[order[i]] = twice_mid;
        k = end;
    }
    return ranks;
}

// uniform in [0, bound): raw draws below the largest multiple of bound, modulo bound
std::size_t uniform_below(std::mt19937_64& engine, std::size_t bound) {
    const std::uint64_t b = bound;
    const std::uint64_t limit =
        std::numeric_limits<std::uint64_t>::max() - std::numeric_limits<std::uint64_t>::max() % b;
    std::uint64_t v = engine();
    while (v >= limit) v = engine();
    return static_cast<std::size_t>(v % b);
}

}  // namespace

double tied_share(std::span<const double> a, std::span<const double> b) {
    std::vector<double> pooled(a.begin(), a.end());
    pooled.insert(pooled.end(), b.begin(), b.end());
    if (pooled.empty()) throw DataError("tied_share: both samples are empty");
    std::sort(pooled.begin(), pooled.end());
    std::size_t tied = 0;
    for (std::size_t k = 0; k < pooled.size();) {
        std::size_t end = k;
        while (end < pooled.size() && pooled[end] == pooled[k]) ++end;
        if (end - k > 1) tied += end - k;
        k = end;
    }
    return static_cast<double>(tied) / static_cast<double>(pooled.size());
}

PermutationP permutation_p(std::span<const double> a, std::span<const double> b, std::size_t exact_limit,
                           std::size_t draws, unsigned long long seed) {
    check_values("a", a);
    check_values("b", b);
    const std::vector<std::int64_t> ranks = doubled_mid_ranks(a, b);
    const std::size_t n = ranks.size();
    // the smaller sample's rank sum carries the statistic: R_a + R_b is fixed
    const bool first_smaller = a.size() <= b.size();
    const std::size_t m = first_smaller ? a.size() : b.size();
    std::int64_t observed = 0;
    for (std::size_t i = 0; i < n; ++i) {
        if ((i < a.size()) == first_smaller) observed += ranks[i];
    }
    // E[2 R] = m (n + 1); compare |2R - E| in integers
    const auto centre = static_cast<std::int64_t>(m * (n + 1));
    const std::int64_t distance = std::llabs(observed - centre);
    const std::int64_t total_rank = std::accumulate(ranks.begin(), ranks.end(), std::int64_t{0});

    PermutationP result;
    const auto max_sum = static_cast<std::size_t>(total_rank);
    if (n * m * (max_sum + 1) <= exact_limit) {
        // ways[k][s]: relabellings of the values seen so far putting k of them,
        // with doubled rank sum s, in the smaller sample
        std::vector<std::vector<double>> ways(m + 1, std::vector<double>(max_sum + 1, 0.0));
        ways[0][0] = 1.0;
        std::size_t reach = 0;  // largest sum reachable so far
        for (std::size_t i = 0; i < n; ++i) {
            const auto r = static_cast<std::size_t>(ranks[i]);
            reach += r;
            for (std::size_t k = std::min(i + 1, m); k >= 1; --k) {
                auto& to = ways[k];
                const auto& from = ways[k - 1];
                for (std::size_t s = std::min(reach, max_sum); s >= r; --s) {
                    to[s] += from[s - r];
                    if (s == r) break;
                }
            }
        }
        double extreme = 0, all = 0;
        for (std::size_t s = 0; s <= max_sum; ++s) {
            const double w = ways[m][s];
            if (w == 0) continue;
            all += w;
            if (std::llabs(static_cast<std::int64_t>(s) - centre) >= distance) extreme += w;
        }
        result.p = std::min(1.0, extreme / all);
        return result;
    }

    // Monte Carlo: partial Fisher-Yates draws of m ranks from a fixed-seed
    // mt19937_64 (its output sequence is specified by the standard), indices
    // by rejection so nothing depends on the library's distributions
    std::mt19937_64 engine(seed);
    std::vector<std::int64_t> pool = ranks;
    std::size_t hits = 0;
    for (std::size_t d = 0; d < draws; ++d) {
        std::int64_t sum = 0;
        for (std::size_t k = 0; k < m; ++k) {
            const std::size_t j = k + uniform_below(engine, n - k);
            std::swap(pool[k], pool[j]);
            sum += pool[k];
        }
        if (std::llabs(sum - centre) >= distance) ++hits;
    }
    result.exact = false;
    result.draws = draws;
    result.p = static_cast<double>(1 + hits) / static_cast<double>(1 + draws);
    result.standard_error = std::sqrt(result.p * (1.0 - result.p) / static_cast<double>(draws));
    return result;
}

}  // namespace stepstone::stats
