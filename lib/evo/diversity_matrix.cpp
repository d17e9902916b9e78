#include "evo/diversity_matrix.hpp"

#include <algorithm>
#include <atomic>
#include <thread>
#include <unordered_map>

#include "core/error.hpp"
#include "core/text.hpp"

namespace stepstone::evo {

// batches of kLanes pairs go to whichever thread is free, and each result lands in its own slot
std::vector<float> pair_distances(std::span<const PositionPair> pairs,
                                  std::span<const Trajectory> trajectories, std::size_t length,
                                  unsigned threads) {
    std::vector<float> distances(pairs.size());
    const std::size_t batches = (pairs.size() + kLanes - 1) / kLanes;
    std::atomic<std::size_t> next_batch{0};

    const auto work = [&] {
        EditDistanceBatch batch;
        const GridCell* first[kLanes];
        const GridCell* second[kLanes];
        for (std::size_t b = next_batch++; b < batches; b = next_batch++) {
            const std::size_t begin = b * kLanes;
            const std::size_t count = std::min(kLanes, pairs.size() - begin);
            for (std::size_t k = 0; k < count; ++k) {
                first[k] = trajectories[pairs[begin + k].first].data();
                second[k] = trajectories[pairs[begin + k].second].data();
            }
            batch.run(std::span(first, count), std::span(second, count), length, &distances[begin]);
        }
    };

    const std::size_t helpers = std::min<std::size_t>(threads > 0 ? threads - 1 : 0, batches > 0 ? batches - 1 : 0);
    std::vector<std::thread> pool;
    pool.reserve(helpers);
    for (std::size_t t = 0; t < helpers; ++t) pool.emplace_back(work);
    work();
    for (auto& thread : pool) thread.join();
    return distances;
}

void DiversityMatrix::update(std::span<const std::uint64_t> ids, std::span<const Trajectory> trajectories,
                             unsigned threads) {
    update(ids, trajectories,
           [threads](std::span<const PositionPair> pairs, std::span<const Trajectory> all,
                     std::size_t length) { return pair_distances(pairs, all, length, threads); });
}

void DiversityMatrix::update(std::span<const std::uint64_t> ids, std::span<const Trajectory> trajectories,
                             const PairDistances& compute) {
    // validate everything before touching the cache
    const std::size_t n = ids.size();
    if (trajectories.size() != n) {
        throw DataError(concat("diversity: ", n, " ids but ", trajectories.size(), " trajectories"));
    }
    const std::size_t length = n > 0 ? trajectories[0].size() : 0;
    for (std::size_t i = 0; i < n; ++i) {
        if (trajectories[i].size() != length) {
            throw DataError(concat("diversity: trajectory ", i, " has ", trajectories[i].size(),
                                   " samples, trajectory 0 has ", length));
        }
    }
    std::unordered_map<std::uint64_t, std::size_t> position;
    position.reserve(n);
    for (std::size_t i = 0; i < n; ++i) {
        if (!position.emplace(ids[i], i).second) throw DataError(concat("diversity: id ", ids[i], " appears twice"));
    }

    // where each new position was in the previous update, if anywhere
    constexpr std::size_t kAbsent = static_cast<std::size_t>(-1);
    std::vector<std::size_t> old_position(n, kAbsent);
    for (std::size_t k = 0; k < ids_.size(); ++k) {
        if (auto it = position.find(ids_[k]); it != position.end()) old_position[it->second] = k;
    }

    // reuse pairs of two known ids, list the others
    std::vector<float> matrix(n * n, 0.0f);
    std::vector<PositionPair> pairs;
    const std::size_t old_n = ids_.size();
    for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t j = i + 1; j < n; ++j) {
            if (old_position[i] != kAbsent && old_position[j] != kAbsent) {
                matrix[i * n + j] = matrix_[old_position[i] * old_n + old_position[j]];
            } else {
                pairs.emplace_back(static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(j));
            }
        }
    }

    // compute the new pairs, then mirror the upper triangle
    const auto distances = compute(pairs, trajectories, length);
    if (distances.size() != pairs.size()) {
        throw Error(concat("diversity: ", pairs.size(), " pairs but ", distances.size(), " distances"));
    }
    for (std::size_t k = 0; k < pairs.size(); ++k) matrix[pairs[k].first * n + pairs[k].second] = distances[k];
    for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t j = i + 1; j < n; ++j) matrix[j * n + i] = matrix[i * n + j];
    }

    ids_.assign(ids.begin(), ids.end());
    matrix_ = std::move(matrix);
    computed_pairs_ = pairs.size();
}

std::vector<double> DiversityMatrix::sums() const { return distance_sums(matrix_, ids_.size()); }

void DiversityMatrix::clear() {
    ids_.clear();
    matrix_.clear();
    computed_pairs_ = 0;
}

std::vector<float> distance_matrix(std::span<const Trajectory> trajectories, unsigned threads) {
    std::vector<std::uint64_t> ids(trajectories.size());
    for (std::size_t i = 0; i < ids.size(); ++i) ids[i] = i;
    DiversityMatrix matrix;
    matrix.update(ids, trajectories, threads);
    std::vector<float> out(ids.size() * ids.size());
    for (std::size_t i = 0; i < ids.size(); ++i) {
        for (std::size_t j = 0; j < ids.size(); ++j) out[i * ids.size() + j] = matrix.distance(i, j);
    }
    return out;
}

std::vector<double> distance_sums(std::span<const float> matrix, std::size_t n) {
    std::vector<double> sums(n, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
        double sum = 0.0;
        for (std::size_t j = 0; j < n; ++j) {
            if (j != i) sum += static_cast<double>(matrix[i * n + j]);
        }
        sums[i] = sum;
    }
    return sums;
}

}  // namespace stepstone::evo
