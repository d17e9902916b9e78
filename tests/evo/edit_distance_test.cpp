#include <catch2/catch.hpp>

#include <algorithm>
#include <vector>

#include "core/rng.hpp"
#include "evo/edit_distance.hpp"

using namespace stepstone;
using namespace stepstone::evo;

namespace {

// a plain full-table optimal string alignment with collectball's costs,
// written independently of the library's versions
float oracle(const Trajectory& a, const Trajectory& b) {
    const std::size_t n = a.size(), m = b.size();
    std::vector<std::vector<float>> d(n + 1, std::vector<float>(m + 1));
    for (std::size_t i = 0; i <= n; ++i) d[i][0] = float(i);
    for (std::size_t j = 0; j <= m; ++j) d[0][j] = float(j);
    for (std::size_t i = 1; i <= n; ++i) {
        for (std::size_t j = 1; j <= m; ++j) {
            const float manhattan = float(std::abs(a[i - 1].x - b[j - 1].x)) + float(std::abs(a[i - 1].y - b[j - 1].y));
            const float cost = manhattan / 12.0f;
            d[i][j] = std::min({d[i - 1][j] + 1.0f, d[i][j - 1] + 1.0f, d[i - 1][j - 1] + cost});
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) {
                d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + cost);
            }
        }
    }
    return d[n][m];
}

Trajectory random_trajectory(Rng& rng, std::size_t length, std::uint64_t width, std::uint64_t height) {
    Trajectory t(length);
    for (auto& cell : t) {
        cell.x = static_cast<std::int16_t>(rng.below(width));
        cell.y = static_cast<std::int16_t>(rng.below(height));
    }
    return t;
}

constexpr EditDistanceBatch::Simd kBothSimd[] = {EditDistanceBatch::Simd::automatic,
                                                 EditDistanceBatch::Simd::baseline};

float batch_one(const Trajectory& a, const Trajectory& b,
                EditDistanceBatch::Simd simd = EditDistanceBatch::Simd::automatic) {
    EditDistanceBatch batch(simd);
    const GridCell* first[] = {a.data()};
    const GridCell* second[] = {b.data()};
    float out = -1.0f;
    batch.run(first, second, a.size(), &out);
    return out;
}

}  // namespace

TEST_CASE("edit distance hand cases", "[evo][diversity]") {
    EditDistance distance;
    const GridCell p{0, 0}, q{6, 0}, r{3, 2}, s{11, 7};
    // identical sequences
    CHECK(distance(Trajectory{p, q, r}, Trajectory{p, q, r}) == 0.0f);
    // one insertion / one deletion cost 1
    CHECK(distance(Trajectory{p, q, r}, Trajectory{p, q, s, r}) == 1.0f);
    CHECK(distance(Trajectory{p, q, s, r}, Trajectory{p, q, r}) == 1.0f);
    CHECK(distance(Trajectory{}, Trajectory{p, q}) == 2.0f);
    // substitution = Manhattan / 12: (0,0) -> (3,2) is 5 / 12
    CHECK(distance(Trajectory{p}, Trajectory{r}) == 5.0f / 12.0f);
    // 18 / 12 = 1.5 stays cheaper than a deletion plus an insertion (2)
    CHECK(distance(Trajectory{p}, Trajectory{s}) == 1.5f);
    // two substitutions in a row add up: 6/12 + 5/12
    CHECK(distance(Trajectory{p, p}, Trajectory{q, r}) == 6.0f / 12.0f + 5.0f / 12.0f);
}

TEST_CASE("a transposition costs the substitution of the current pair", "[evo][diversity]") {
    // (p q) vs (q p) with p, q 6 cells apart: two substitutions cost 0.5 + 0.5,
    // collectball's transposition D[0][0] + cost(q, p) = 0.5 (standard OSA would give 1)
    EditDistance distance;
    const GridCell p{0, 0}, q{6, 0};
    CHECK(distance(Trajectory{p, q}, Trajectory{q, p}) == 0.5f);
    CHECK(edit_distance_full_table(Trajectory{p, q}, Trajectory{q, p}) == 0.5f);
    for (auto simd : kBothSimd) CHECK(batch_one(Trajectory{p, q}, Trajectory{q, p}, simd) == 0.5f);
    // far apart, substitutions would cost 1.5 + 1.5, two indels 2; the swap costs 1.5
    const GridCell s{11, 7};
    CHECK(distance(Trajectory{p, s}, Trajectory{s, p}) == 1.5f);
}

TEST_CASE("every implementation equals a plain full table on random sequences", "[evo][diversity]") {
    Rng rng(51);
    EditDistance rows;
    for (int trial = 0; trial < 400; ++trial) {
        // small boards make equal cells and swapped pairs frequent
        const std::uint64_t width = 1 + rng.below(12), height = 1 + rng.below(8);
        const std::size_t length = trial < 300 ? 1 + rng.below(80) : 80;
        const auto a = random_trajectory(rng, length, width, height);
        auto b = random_trajectory(rng, length, width, height);
        if (trial % 3 == 0) {
            b = a;  // a near-copy with swaps and edits
            for (std::size_t k = 0; k + 1 < length; k += 1 + rng.below(6)) std::swap(b[k], b[k + 1]);
            b[rng.below(length)] = GridCell{3, 3};
        }
        const float want = oracle(a, b);
        REQUIRE(rows(a, b) == want);
        REQUIRE(rows(b, a) == want);  // symmetric, exactly
        REQUIRE(edit_distance_full_table(a, b) == want);
        for (auto simd : kBothSimd) REQUIRE(batch_one(a, b, simd) == want);
    }
    // sequences of different lengths (rows and full table only)
    for (int trial = 0; trial < 100; ++trial) {
        const auto a = random_trajectory(rng, rng.below(30), 5, 5);
        const auto b = random_trajectory(rng, rng.below(30), 5, 5);
        REQUIRE(rows(a, b) == oracle(a, b));
        REQUIRE(edit_distance_full_table(a, b) == oracle(a, b));
    }
}

TEST_CASE("sixteen pairs in lanes give the distances of each pair alone", "[evo][diversity]") {
    Rng rng(52);
    std::vector<Trajectory> pool;
    for (int k = 0; k < 40; ++k) pool.push_back(random_trajectory(rng, 80, 4, 4));
    EditDistanceBatch vectors;
    EditDistanceBatch baseline(EditDistanceBatch::Simd::baseline);
    CHECK(!baseline.uses_avx2());
    for (std::size_t count : {std::size_t{16}, std::size_t{7}, std::size_t{1}}) {
        std::vector<const GridCell*> first, second;
        std::vector<std::pair<std::size_t, std::size_t>> pairs;
        for (std::size_t k = 0; k < count; ++k) {
            const auto i = rng.below(pool.size()), j = rng.below(pool.size());
            pairs.emplace_back(i, j);
            first.push_back(pool[i].data());
            second.push_back(pool[j].data());
        }
        for (auto* batch : {&vectors, &baseline}) {
            std::vector<float> out(count);
            batch->run(first, second, 80, out.data());
            for (std::size_t k = 0; k < count; ++k) {
                CHECK(out[k] == oracle(pool[pairs[k].first], pool[pairs[k].second]));
            }
        }
    }
}

TEST_CASE("the batch handles the whole int16 range of cells and any length", "[evo][diversity]") {
    // Manhattan distances up to 2 x 65535, and lengths that are not 80
    Rng rng(53);
    const GridCell low{-32768, -32768}, high{32767, 32767};
    for (auto simd : kBothSimd) {
        CHECK(batch_one(Trajectory{low}, Trajectory{high}, simd) == 2.0f);  // an insertion and a deletion
        CHECK(batch_one(Trajectory{low, high}, Trajectory{high, low}, simd) ==
              oracle({low, high}, {high, low}));
        CHECK(batch_one(Trajectory{}, Trajectory{}, simd) == 0.0f);
    }
    for (int trial = 0; trial < 200; ++trial) {
        const std::size_t length = 1 + rng.below(40);
        Trajectory a(length), b(length);
        for (auto* t : {&a, &b}) {
            for (auto& cell : *t) {
                // mostly a few far-apart values, so equal cells and swaps still occur
                const auto pick = [&rng] {
                    const std::int16_t values[] = {-32768, -1, 0, 5, 32767};
                    if (rng.below(4) != 0) return values[rng.below(5)];
                    return static_cast<std::int16_t>(static_cast<std::int64_t>(rng.below(65536)) - 32768);
                };
                cell.x = pick();
                cell.y = pick();
            }
        }
        if (trial % 2 == 0 && length > 1) {
            b = a;
            std::swap(b[0], b[1]);
        }
        const float want = oracle(a, b);
        for (auto simd : kBothSimd) REQUIRE(batch_one(a, b, simd) == want);
    }
}
