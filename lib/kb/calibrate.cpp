#include "kb/calibrate.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "core/text.hpp"
#include "kb/distance.hpp"

namespace stepstone::kb {

double calibrate_delta(Segments policy, std::size_t neighbours) {
    if (neighbours == 0) throw DataError("calibrate: neighbours must be >= 1, got 0");
    if (policy.dim == 0) throw DataError("calibrate: segment dimension must be >= 1, got 0");
    const std::size_t n = policy.size();
    if (n < 2) throw DataError(concat("calibrate: the policy has ", n, " segment(s), at least 2 are needed"));
    for (float v : policy.values.first(n * policy.dim)) {
        if (!std::isfinite(v)) throw DataError("calibrate: the policy has a non-finite value");
    }

    // every pairwise distance, then for each segment the mean of its k smallest
    const std::size_t k = std::min(neighbours, n - 1);
    std::vector<double> dist(n * n, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t j = i + 1; j < n; ++j) {
            const double d = std::sqrt(squared_distance(policy[i].data(), policy[j].data(), policy.dim));
            dist[i * n + j] = d;
            dist[j * n + i] = d;
        }
    }
    double total = 0.0;
    std::vector<double> row;
    for (std::size_t i = 0; i < n; ++i) {
        row.clear();
        for (std::size_t j = 0; j < n; ++j)
            if (j != i) row.push_back(dist[i * n + j]);
        std::partial_sort(row.begin(), row.begin() + static_cast<std::ptrdiff_t>(k), row.end());
        double sum = 0.0;
        for (std::size_t m = 0; m < k; ++m) sum += row[m];
        total += sum / static_cast<double>(k);
    }
    return total / static_cast<double>(n);
}

std::vector<DeltaSize> kb_sizes(const KbParams& params, std::span<const Segments> policies,
                                std::span<const double> deltas) {
    std::vector<DeltaSize> sizes;
    sizes.reserve(deltas.size());
    for (const double delta : deltas) {
        KbParams p = params;
        p.delta = delta;
        KnowledgeBase kb(p);
        const std::uint32_t source = kb.add_source("calibrate");
        for (const Segments& policy : policies) kb.observe(policy, 0.0, Origin{source, 0});
        sizes.push_back(DeltaSize{delta, kb.size()});
    }
    return sizes;
}

}  // namespace stepstone::kb
