#include "evo/pareto.hpp"

#include <algorithm>
#include <numeric>

#include "core/assert.hpp"

namespace stepstone::evo {

bool dominates(std::span<const double> a, std::span<const double> b) {
    STEPSTONE_ASSERT(a.size() == b.size());
    bool better_somewhere = false;
    for (std::size_t k = 0; k < a.size(); ++k) {
        if (a[k] < b[k]) return false;
        if (a[k] > b[k]) better_somewhere = true;
    }
    return better_somewhere;
}

std::vector<std::vector<std::size_t>> non_dominated_fronts(const Objectives& objectives) {
    const std::size_t n = objectives.size();
    std::vector<std::vector<std::size_t>> dominated(n);  // S_p: whom p dominates
    std::vector<std::size_t> domination_count(n, 0);      // n_p: how many dominate p

    // every pair once
    for (std::size_t p = 0; p < n; ++p) {
        for (std::size_t q = p + 1; q < n; ++q) {
            if (dominates(objectives[p], objectives[q])) {
                dominated[p].push_back(q);
                ++domination_count[q];
            } else if (dominates(objectives[q], objectives[p])) {
                dominated[q].push_back(p);
                ++domination_count[p];
            }
        }
    }

    // peel the fronts
    std::vector<std::vector<std::size_t>> fronts;
    std::vector<std::size_t> current;
    for (std::size_t p = 0; p < n; ++p) {
        if (domination_count[p] == 0) current.push_back(p);
    }
    while (!current.empty()) {
        std::vector<std::size_t> next;
        for (std::size_t p : current) {
            for (std::size_t q : dominated[p]) {
                if (--domination_count[q] == 0) next.push_back(q);
            }
        }
        std::sort(next.begin(), next.end());
        fronts.push_back(std::move(current));
        current = std::move(next);
    }
    return fronts;
}

std::vector<double> crowding_distance(const Objectives& objectives, std::span<const std::size_t> front) {
    const std::size_t size = front.size();
    if (size <= 2) return std::vector<double>(size, kBoundaryCrowding);

    std::vector<double> distance(size, 0.0);
    std::vector<std::size_t> order(size);
    const std::size_t dimensions = objectives[front[0]].size();
    for (std::size_t m = 0; m < dimensions; ++m) {
        // positions in the front, sorted by objective m, ties by individual index
        std::iota(order.begin(), order.end(), std::size_t{0});
        const auto value = [&](std::size_t position) { return objectives[front[position]][m]; };
        std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
            return value(a) != value(b) ? value(a) < value(b) : front[a] < front[b];
        });
        const double low = value(order.front());
        const double high = value(order.back());

        // ends are set, not added to (sferes2 crowd.hpp)
        distance[order.front()] = kBoundaryCrowding;
        distance[order.back()] = kBoundaryCrowding;
        if (high == low) continue;
        for (std::size_t k = 1; k + 1 < size; ++k) {
            distance[order[k]] += (value(order[k + 1]) - value(order[k - 1])) / (high - low);
        }
    }
    return distance;
}

Ranking rank_and_crowd(const Objectives& objectives) {
    Ranking ranking;
    ranking.fronts = non_dominated_fronts(objectives);
    ranking.rank.assign(objectives.size(), 0);
    ranking.crowding.assign(objectives.size(), 0.0);
    for (std::size_t r = 0; r < ranking.fronts.size(); ++r) {
        const auto& front = ranking.fronts[r];
        const auto crowding = crowding_distance(objectives, front);
        for (std::size_t k = 0; k < front.size(); ++k) {
            ranking.rank[front[k]] = r;
            ranking.crowding[front[k]] = crowding[k];
        }
    }
    return ranking;
}

}  // namespace stepstone::evo
