#include "evo/selection.hpp"

#include <algorithm>
#include <numeric>

#include "core/error.hpp"
#include "core/text.hpp"

namespace stepstone::evo {

std::size_t tournament(std::size_t a, std::size_t b, const Objectives& objectives,
                       std::span<const double> crowding, Rng& rng) {
    if (dominates(objectives[a], objectives[b])) return a;
    if (dominates(objectives[b], objectives[a])) return b;
    if (crowding[a] > crowding[b]) return a;
    if (crowding[a] < crowding[b]) return b;
    return rng.bernoulli(0.5) ? a : b;
}

std::vector<std::size_t> select_parents(const Objectives& objectives, std::span<const double> crowding,
                                        Rng& rng) {
    const std::size_t n = objectives.size();
    if (n == 0 || n % 4 != 0) {
        throw DataError(concat("population size must be a positive multiple of 4, got ", n));
    }
    if (crowding.size() != n) {
        throw DataError(concat("selection needs one crowding distance per parent: ", crowding.size(),
                               " for ", n, " parents"));
    }

    // two independent permutations of the parents
    std::vector<std::size_t> a1(n), a2(n);
    std::iota(a1.begin(), a1.end(), std::size_t{0});
    std::iota(a2.begin(), a2.end(), std::size_t{0});
    rng.shuffle(std::span<std::size_t>(a1));
    rng.shuffle(std::span<std::size_t>(a2));

    // four tournaments per block of four positions
    std::vector<std::size_t> winners;
    winners.reserve(n);
    for (std::size_t i = 0; i < n; i += 4) {
        winners.push_back(tournament(a1[i], a1[i + 1], objectives, crowding, rng));
        winners.push_back(tournament(a1[i + 2], a1[i + 3], objectives, crowding, rng));
        winners.push_back(tournament(a2[i], a2[i + 1], objectives, crowding, rng));
        winners.push_back(tournament(a2[i + 2], a2[i + 3], objectives, crowding, rng));
    }
    return winners;
}

Survivors survivors(const Objectives& objectives, std::size_t count) {
    if (count > objectives.size()) {
        throw DataError(concat("cannot keep ", count, " of ", objectives.size(), " individuals"));
    }
    const Ranking ranking = rank_and_crowd(objectives);
    Survivors kept;
    const auto keep = [&](std::size_t index) {
        kept.indices.push_back(index);
        kept.crowding.push_back(ranking.crowding[index]);
        kept.rank.push_back(ranking.rank[index]);
    };

    // whole fronts while they fit strictly below count (sferes2's test)
    std::size_t r = 0;
    for (; r < ranking.fronts.size() && kept.indices.size() + ranking.fronts[r].size() < count; ++r) {
        for (std::size_t index : ranking.fronts[r]) keep(index);
    }

    // the best-spread members of the next front fill the rest
    if (kept.indices.size() < count) {
        std::vector<std::size_t> last = ranking.fronts[r];
        std::sort(last.begin(), last.end(), [&](std::size_t a, std::size_t b) {
            const double ca = ranking.crowding[a];
            const double cb = ranking.crowding[b];
            return ca != cb ? ca > cb : a < b;
        });
        const std::size_t missing = count - kept.indices.size();
        for (std::size_t k = 0; k < missing; ++k) keep(last[k]);
    }
    return kept;
}

}  // namespace stepstone::evo
