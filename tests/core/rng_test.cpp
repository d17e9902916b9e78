#include <catch2/catch.hpp>

#include <algorithm>
#include <numeric>
#include <set>
#include <vector>

#include "core/rng.hpp"

using namespace stepstone;

TEST_CASE("mix64 is splitmix64's output function", "[core][rng]") {
    // splitmix64 seeded with 0 yields 0xe220a8397b1dcdaf, 0x6e789e6aa1b965f4
    // (reference sequence of Vigna's splitmix64.c); mix64(x) is the output for state x
    CHECK(mix64(0) == 0xe220a8397b1dcdafULL);
    CHECK(mix64(0x9e3779b97f4a7c15ULL) == 0x6e789e6aa1b965f4ULL);
}

TEST_CASE("a stream is reproducible from its coordinates", "[core][rng][determinism]") {
    Rng a(42, 7, 3, Purpose::mutation);
    Rng b(42, 7, 3, Purpose::mutation);
    for (int i = 0; i < 1000; ++i) REQUIRE(a.next() == b.next());
}

TEST_CASE("streams of neighbouring coordinates are distinct and uncorrelated", "[core][rng]") {
    // every coordinate change must give a different seed
    std::set<std::uint64_t> seeds;
    for (std::uint64_t g = 0; g < 20; ++g)
        for (std::uint64_t i = 0; i < 20; ++i)
            for (auto p : {Purpose::mutation, Purpose::evaluation, Purpose::selection})
                seeds.insert(derive_seed(1, g, i, p));
    CHECK(seeds.size() == 20u * 20u * 3u);
    // swapping generation and individual must not give the same stream
    CHECK(derive_seed(1, 2, 3, Purpose::mutation) != derive_seed(1, 3, 2, Purpose::mutation));

    // E[(u - 1/2)(v - 1/2)] = 0 for independent uniforms; with n = 200000 the
    // standard error of the mean product is (1/12)/sqrt(n) ~ 1.9e-4, 6 sigma ~ 1.1e-3
    Rng a(5, 0, 0, Purpose::mutation);
    Rng b(5, 0, 1, Purpose::mutation);
    double sum = 0;
    const int n = 200000;
    for (int k = 0; k < n; ++k) sum += (a.uniform() - 0.5) * (b.uniform() - 0.5);
    CHECK(std::abs(sum / n) < 1.1e-3);
}

TEST_CASE("uniform lies in the half-open unit interval with mean 1/2 and variance 1/12", "[core][rng]") {
    Rng rng(123);
    const int n = 200000;
    double sum = 0, sum_sq = 0;
    for (int k = 0; k < n; ++k) {
        const double u = rng.uniform();
        REQUIRE(u >= 0.0);
        REQUIRE(u < 1.0);
        sum += u;
        sum_sq += u * u;
    }
    const double mean = sum / n;
    // standard error of the mean: sqrt(1/12 / n) ~ 6.5e-4; 6 sigma
    CHECK(std::abs(mean - 0.5) < 3.9e-3);
    CHECK(std::abs(sum_sq / n - mean * mean - 1.0 / 12.0) < 2e-3);
}

TEST_CASE("below(n) is unbiased: chi-square over 10 cells", "[core][rng]") {
    Rng rng(99);
    std::vector<int> counts(10, 0);
    const int n = 100000;
    for (int k = 0; k < n; ++k) counts[static_cast<std::size_t>(rng.below(10))]++;
    double chi2 = 0;
    for (int c : counts) chi2 += (c - n / 10.0) * (c - n / 10.0) / (n / 10.0);
    // chi-square with 9 degrees of freedom: P(X > 27.88) = 0.001
    CHECK(chi2 < 27.88);
}

TEST_CASE("shuffle gives a permutation", "[core][rng]") {
    Rng rng(7);
    std::vector<int> values(100);
    std::iota(values.begin(), values.end(), 0);
    rng.shuffle(std::span<int>(values));
    auto sorted = values;
    std::sort(sorted.begin(), sorted.end());
    for (int i = 0; i < 100; ++i) REQUIRE(sorted[static_cast<std::size_t>(i)] == i);
    CHECK(!std::is_sorted(values.begin(), values.end()));
}
