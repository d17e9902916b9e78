#include "reference/edit_distance_baseline.hpp"

#include <algorithm>
#include <cstdlib>

#include "core/rng.hpp"

namespace stepstone::reference {

namespace {

bool same(const GridCell& p, const GridCell& q) { return p.x == q.x && p.y == q.y; }

float substitution(const GridCell& p, const GridCell& q) {
    if (same(p, q)) return 0.0f;
    return static_cast<float>(std::abs(p.x - q.x) + std::abs(p.y - q.y)) / 12.0f;
}

}  // namespace

float edit_distance_baseline(std::span<const GridCell> a, std::span<const GridCell> b) {
    const std::size_t rows = a.size() + 1;
    const std::size_t cols = b.size() + 1;
    // a new table per pair, as the original
    float* table = new float[rows * cols];
    auto at = [&](std::size_t i, std::size_t j) -> float& { return table[i + rows * j]; };
    for (std::size_t i = 0; i < rows; ++i) {
        for (std::size_t j = 0; j < cols; ++j) at(i, j) = 0.0f;
    }
    for (std::size_t i = 0; i < rows; ++i) at(i, 0) = static_cast<float>(i);
    for (std::size_t j = 0; j < cols; ++j) at(0, j) = static_cast<float>(j);

    for (std::size_t i = 1; i < rows; ++i) {
        for (std::size_t j = 1; j < cols; ++j) {
            const float cost = substitution(a[i - 1], b[j - 1]);
            float best = std::min(at(i - 1, j) + 1, std::min(at(i, j - 1) + 1, at(i - 1, j - 1) + cost));
            // transposition of adjacent samples
            if (i > 1 && j > 1 && same(a[i - 1], b[j - 2]) && same(a[i - 2], b[j - 1])) {
                best = std::min(best, at(i - 2, j - 2) + cost);
            }
            at(i, j) = best;
        }
    }
    const float result = at(rows - 1, cols - 1);
    delete[] table;
    return result;
}

std::vector<double> diversity_baseline(const std::vector<std::vector<GridCell>>& trajectories) {
    std::vector<double> sums(trajectories.size(), 0.0);
    for (std::size_t i = 0; i < trajectories.size(); ++i) {
        for (std::size_t j = i + 1; j < trajectories.size(); ++j) {
            const double d = edit_distance_baseline(trajectories[i], trajectories[j]);
            sums[i] += d;
            sums[j] += d;
        }
    }
    return sums;
}

std::vector<std::vector<GridCell>> random_trajectories(int count, int length, std::uint64_t seed) {
    Rng rng(seed);
    std::vector<std::vector<GridCell>> out(static_cast<std::size_t>(std::max(count, 0)));
    for (auto& trajectory : out) {
        GridCell cell{static_cast<std::int32_t>(rng.below(12)), static_cast<std::int32_t>(rng.below(8))};
        for (int k = 0; k < length; ++k) {
            trajectory.push_back(cell);
            // stay (1 in 3) or step to a neighbour inside the board
            const auto move = rng.below(6);
            if (move == 2 && cell.x > 0) --cell.x;
            if (move == 3 && cell.x < 11) ++cell.x;
            if (move == 4 && cell.y > 0) --cell.y;
            if (move == 5 && cell.y < 7) ++cell.y;
        }
    }
    return out;
}

}  // namespace stepstone::reference
