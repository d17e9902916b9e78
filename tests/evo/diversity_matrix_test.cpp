#include <catch2/catch.hpp>

#include <numeric>
#include <vector>

#include "core/error.hpp"
#include "core/rng.hpp"
#include "evo/diversity_matrix.hpp"

using namespace stepstone;
using namespace stepstone::evo;
using Catch::Matchers::Equals;

namespace {

std::vector<Trajectory> random_trajectories(Rng& rng, std::size_t count) {
    std::vector<Trajectory> out(count, Trajectory(80));
    for (auto& t : out) {
        for (auto& cell : t) {
            // the reachable 12 x 8 board of collectball
            cell = GridCell{static_cast<std::int16_t>(rng.below(12)), static_cast<std::int16_t>(rng.below(8))};
        }
    }
    return out;
}

// collectball's modifier the plain way: full matrix by the table-per-pair DP, row sums
std::vector<double> plain_sums(const std::vector<Trajectory>& trajectories) {
    const std::size_t n = trajectories.size();
    std::vector<double> sums(n, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t j = 0; j < n; ++j) {
            if (i != j) sums[i] += static_cast<double>(edit_distance_full_table(trajectories[i], trajectories[j]));
        }
    }
    return sums;
}

}  // namespace

TEST_CASE("diversity sums equal the plain full computation", "[evo][diversity]") {
    Rng rng(61);
    const auto trajectories = random_trajectories(rng, 37);
    std::vector<std::uint64_t> ids(37);
    std::iota(ids.begin(), ids.end(), std::uint64_t{100});
    DiversityMatrix matrix;
    matrix.update(ids, trajectories, 1);
    CHECK(matrix.computed_pairs() == 37 * 36 / 2);
    CHECK(matrix.sums() == plain_sums(trajectories));
    CHECK(matrix.distance(3, 3) == 0.0f);
    CHECK(matrix.distance(3, 5) == matrix.distance(5, 3));
}

TEST_CASE("cached distances of surviving individuals are reused and still exact", "[evo][diversity]") {
    Rng rng(62);
    auto trajectories = random_trajectories(rng, 40);
    std::vector<std::uint64_t> ids(40);
    std::iota(ids.begin(), ids.end(), std::uint64_t{0});
    DiversityMatrix matrix;
    matrix.update(ids, trajectories, 2);

    // next generation: 20 survivors (in another order) and 20 new individuals
    std::vector<std::uint64_t> next_ids;
    std::vector<Trajectory> next;
    for (std::uint64_t k = 0; k < 20; ++k) {
        next_ids.push_back(39 - 2 * k);
        next.push_back(trajectories[39 - 2 * k]);
    }
    const auto fresh = random_trajectories(rng, 20);
    for (std::uint64_t k = 0; k < 20; ++k) {
        next_ids.push_back(1000 + k);
        next.push_back(fresh[k]);
    }
    matrix.update(next_ids, next, 2);
    // new pairs: 20 * 19 / 2 among the new plus 20 * 20 with the survivors
    CHECK(matrix.computed_pairs() == 190 + 400);
    CHECK(matrix.sums() == plain_sums(next));
}

TEST_CASE("diversity results do not depend on the thread count", "[evo][diversity][determinism]") {
    Rng rng(63);
    const auto trajectories = random_trajectories(rng, 70);
    std::vector<std::uint64_t> ids(70);
    std::iota(ids.begin(), ids.end(), std::uint64_t{0});
    std::vector<std::vector<double>> sums;
    for (unsigned threads : {1u, 2u, 4u}) {
        DiversityMatrix matrix;
        matrix.update(ids, trajectories, threads);
        sums.push_back(matrix.sums());
    }
    CHECK(sums[0] == sums[1]);
    CHECK(sums[0] == sums[2]);
    CHECK(distance_sums(distance_matrix(trajectories, 3), 70) == sums[0]);
}

TEST_CASE("bad diversity input is refused before the cache changes", "[evo][diversity][errors]") {
    Rng rng(64);
    const auto trajectories = random_trajectories(rng, 3);
    DiversityMatrix matrix;
    const std::vector<std::uint64_t> repeated{1, 2, 1};
    CHECK_THROWS_AS(matrix.update(repeated, trajectories), DataError);
    CHECK_THROWS_WITH(matrix.update(repeated, trajectories), Equals("diversity: id 1 appears twice"));
    const std::vector<std::uint64_t> two{1, 2};
    CHECK_THROWS_WITH(matrix.update(two, trajectories), Equals("diversity: 2 ids but 3 trajectories"));
    auto ragged = trajectories;
    ragged[2].pop_back();
    const std::vector<std::uint64_t> three{1, 2, 3};
    CHECK_THROWS_WITH(matrix.update(three, ragged),
                      Equals("diversity: trajectory 2 has 79 samples, trajectory 0 has 80"));
    CHECK(matrix.size() == 0);
}

TEST_CASE("distances computed elsewhere, pair by pair, give the same diversity", "[evo][diversity][mpi]") {
    Rng rng(65);
    const auto trajectories = random_trajectories(rng, 30);
    std::vector<std::uint64_t> ids(30);
    std::iota(ids.begin(), ids.end(), std::uint64_t{0});
    std::size_t asked = 0;
    // what a rank of an MPI job does: its own share of the pairs, here the table-per-pair DP, last pair first
    const PairDistances elsewhere = [&](std::span<const PositionPair> pairs, std::span<const Trajectory> all,
                                        std::size_t length) {
        CHECK(length == 80);
        asked += pairs.size();
        std::vector<float> out(pairs.size());
        for (std::size_t k = pairs.size(); k-- > 0;) {
            REQUIRE(pairs[k].first < pairs[k].second);
            out[k] = edit_distance_full_table(all[pairs[k].first], all[pairs[k].second]);
        }
        return out;
    };
    DiversityMatrix matrix;
    matrix.update(ids, trajectories, elsewhere);
    CHECK(asked == 30 * 29 / 2);
    CHECK(matrix.sums() == plain_sums(trajectories));
    // pair_distances over a split of the pairs equals it whole
    const std::vector<PositionPair> pairs{{0, 1}, {2, 9}, {4, 29}, {7, 8}, {3, 5}};
    const auto whole = pair_distances(pairs, trajectories, 80, 2);
    auto split = pair_distances(std::span(pairs).first(2), trajectories, 80, 1);
    const auto rest = pair_distances(std::span(pairs).subspan(2), trajectories, 80, 1);
    split.insert(split.end(), rest.begin(), rest.end());
    CHECK(split == whole);
    CHECK(whole[1] == edit_distance_full_table(trajectories[2], trajectories[9]));

    // a computer that loses a distance is refused, and the cache is left as it was
    const PairDistances short_one = [&](std::span<const PositionPair> p, std::span<const Trajectory> all,
                                        std::size_t length) {
        auto out = pair_distances(p, all, length, 1);
        out.pop_back();
        return out;
    };
    std::vector<std::uint64_t> next_ids(ids.begin(), ids.end());
    next_ids.back() = 500;
    CHECK_THROWS_WITH(matrix.update(next_ids, trajectories, short_one),
                      Equals("diversity: 29 pairs but 28 distances"));
    CHECK(matrix.sums() == plain_sums(trajectories));
}
