// `diversity`: one generation's edit distances, lib/evo against the
// original-style DP that allocates a table per pair.

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "bench/cases.hpp"
#include "core/error.hpp"
#include "evo/diversity_matrix.hpp"
#include "reference/edit_distance_baseline.hpp"

namespace stepstone::bench {

using namespace stepstone::reference;  // the baselines

namespace {

// the paper's mixed population: 400 trajectories of 80 cells, 79,800 pairs
constexpr int kFullTrajectories = 400;
constexpr int kQuickTrajectories = 60;
constexpr int kCells = 80;

Workload make_diversity_workload(Size size) {
    const int n = size == Size::full ? kFullTrajectories : kQuickTrajectories;
    const auto pairs = static_cast<std::uint64_t>(n) * static_cast<std::uint64_t>(n - 1) / 2;
    auto baseline_data =
        std::make_shared<const std::vector<std::vector<GridCell>>>(random_trajectories(n, kCells, 5));
    auto candidate_data = std::make_shared<std::vector<evo::Trajectory>>();
    for (const auto& t : *baseline_data) {
        evo::Trajectory converted;
        for (const auto& c : t)
            converted.push_back({static_cast<std::int16_t>(c.x), static_cast<std::int16_t>(c.y)});
        candidate_data->push_back(std::move(converted));
    }

    // one core: the candidate's single-threaded matrix, then the sums
    auto baseline_sums = std::make_shared<std::vector<double>>();
    auto candidate_sums = std::make_shared<std::vector<double>>();
    Work baseline = [baseline_data, baseline_sums, pairs] {
        *baseline_sums = diversity_baseline(*baseline_data);
        return pairs;
    };
    Work candidate = [candidate_data, candidate_sums, pairs, n] {
        const auto matrix = evo::distance_matrix(*candidate_data, 1);
        *candidate_sums = evo::distance_sums(matrix, static_cast<std::size_t>(n));
        return pairs;
    };

    // both sides must compute the same objective
    baseline();
    candidate();
    for (std::size_t i = 0; i < baseline_sums->size(); ++i) {
        const double a = (*baseline_sums)[i];
        const double b = (*candidate_sums)[i];
        if (!(std::abs(a - b) <= 1e-6 * std::max(1.0, std::abs(a)))) {
            throw DataError("bench diversity: sums differ for trajectory " + std::to_string(i) + ": " +
                            std::to_string(a) + " vs " + std::to_string(b));
        }
    }
    return Workload{baseline, candidate};
}

}  // namespace

void add_diversity_cases(Registry& registry) {
    registry.add(
        Case{"diversity", "pairs",
             "one generation's edit distances (400 x 80 cells, 79,800 pairs), one core: lib/evo vs a table "
             "allocated per pair",
             10.0, make_diversity_workload});
}

}  // namespace stepstone::bench
