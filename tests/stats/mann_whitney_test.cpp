#include "stats/mann_whitney.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <vector>

#include "core/error.hpp"

using namespace stepstone;
using namespace stepstone::stats;

// Expected values: by hand where the comment shows the working, otherwise from
// tests/stats/oracle.py (pure Python: pairwise U, exact p by enumerating every
// rank assignment or by exact integer Gaussian-binomial coefficients, normal
// approximation with math.erfc), which also checked each of them against
// scipy 1.10.1 mannwhitneyu(x, y, alternative="two-sided", method="auto").

namespace {

constexpr double kRel = 1e-12;

std::vector<double> over_24(const std::vector<int>& k) {
    std::vector<double> out;
    for (int x : k) out.push_back(x / 24.0);
    return out;
}

// swapping the samples mirrors U and keeps p
void check_swap(const std::vector<double>& a, const std::vector<double>& b) {
    const MannWhitney ab = mann_whitney_u(a, b);
    const MannWhitney ba = mann_whitney_u(b, a);
    CHECK(ba.u == static_cast<double>(a.size() * b.size()) - ab.u);
    CHECK(ba.p == ab.p);
    CHECK(ba.method == ab.method);
}

}  // namespace

TEST_CASE("mann_whitney_u: Shier's diagnosis ages, the published example", "[stats]") {
    // Shier (2004), "Statistics: 2.3 The Mann-Whitney U Test" (also SciPy's
    // docstring example): U_M = 17, p = 0.11.
    // By hand: 19 beats 11 12 17, 22 beats all 4, 16 beats 11 12, 29 and 24 beat
    // all 4: U = 3 + 4 + 2 + 4 + 4 = 17; max(17, 20 - 17) = 17.
    // n_b = 4 <= 8, no ties: exact. P(U >= 17) = P(U <= 3); the assignments with
    // U = 0, 1, 2, 3 are the partitions of u into at most 4 parts <= 5:
    // 1 + 1 + 2 + 3 = 7 of C(9, 4) = 126, so p = 2 * 7 / 126 = 1 / 9.
    const std::vector<double> males{19, 22, 16, 29, 24};
    const std::vector<double> females{20, 11, 17, 12};
    const MannWhitney r = mann_whitney_u(males, females);
    CHECK(r.u == 17.0);
    CHECK(r.p == Approx(1.0 / 9.0).epsilon(kRel));
    CHECK(r.method == Method::exact);
    check_swap(males, females);
}

TEST_CASE("mann_whitney_u: Hollander and Wolfe's permeability data from R's wilcox.test help", "[stats]") {
    // Hollander & Wolfe (1973), p. 69; R's ?wilcox.test prints W = 35 and the
    // one-sided p-value 0.1272 for alternative = "greater"; two-sided is twice it.
    // oracle.py: U = 35, p = 0.2544122544122544 (exact, enumeration of C(15, 5) = 3003).
    const std::vector<double> x{0.80, 0.83, 1.89, 1.04, 1.45, 1.38, 1.91, 1.64, 0.73, 1.46};
    const std::vector<double> y{1.15, 0.88, 0.90, 0.74, 1.21};
    const MannWhitney r = mann_whitney_u(x, y);
    CHECK(r.u == 35.0);
    CHECK(r.p == Approx(0.2544122544122544).epsilon(kRel));
    CHECK(r.p / 2 == Approx(0.1272).margin(5e-5));
    CHECK(r.method == Method::exact);
    check_swap(x, y);
}

TEST_CASE("mann_whitney_u: complete separation of 2 and 3 values", "[stats]") {
    // By hand: U_a = 0, U = max(0, 6) = 6; P(U >= 6) = P(U <= 0) = 1 / C(5, 2):
    // p = 2 / 10.
    const std::vector<double> a{1, 2};
    const std::vector<double> b{3, 4, 5};
    const MannWhitney r = mann_whitney_u(a, b);
    CHECK(r.u == 0.0);
    CHECK(r.p == Approx(0.2).epsilon(kRel));
    CHECK(r.method == Method::exact);
    check_swap(a, b);
}

TEST_CASE("mann_whitney_u: a small sample with ties uses the normal approximation", "[stats]") {
    // By hand: U_a = 0 (1 vs 2, 3) + 0.5 + 0.5 (each 2 vs 2, 3) = 1, U = max(1, 5) = 5.
    // The value 2 occurs 3 times: sum(t^3 - t) = 24; n = 5, mu = 3,
    // sigma^2 = 6 / 12 * (6 - 24 / 20) = 2.4, z = (5 - 3 - 0.5) / sqrt(2.4) = 0.968246,
    // p = erfc(z / sqrt 2) = 0.33292160806556603 (oracle.py; scipy 0.3329216080655659).
    const std::vector<double> a{1, 2, 2};
    const std::vector<double> b{2, 3};
    const MannWhitney r = mann_whitney_u(a, b);
    CHECK(r.u == 1.0);
    CHECK(r.p == Approx(0.33292160806556603).epsilon(kRel));
    CHECK(r.method == Method::asymptotic);
    check_swap(a, b);
}

TEST_CASE("mann_whitney_u: 20 against 20 without ties", "[stats]") {
    // oracle.py: U = 295, normal approximation (both sizes > 8),
    // sigma^2 = 400 / 12 * 41, z = (295 - 200 - 0.5) / sigma, p = 0.010581211443165657
    // (scipy 0.010581211443165648).
    const std::vector<double> a{0.628, 0.48,  0.73,  0.288, 0.587, 0.596, 0.457, 0.516, 0.625, 0.296,
                                0.614, 0.717, 0.439, 0.808, 0.633, 0.578, 0.543, 0.706, 0.645, 0.454};
    const std::vector<double> b{0.537, 0.227, 0.574, 0.23,  0.148, 0.327, 0.643, 0.55,  0.34,  0.487,
                                0.37,  0.646, 0.231, 0.305, 0.255, 0.165, 0.615, 0.666, 0.542, 0.329};
    const MannWhitney r = mann_whitney_u(a, b);
    CHECK(r.u == 295.0);
    CHECK(r.p == Approx(0.010581211443165657).epsilon(kRel));
    CHECK(r.method == Method::asymptotic);
    check_swap(a, b);
}

TEST_CASE("mann_whitney_u: 20 against 20 rewards k/24 with many zeros", "[stats]") {
    // Ties within and across the samples (19 zeros in the pooled sample).
    // oracle.py: U = 231.5, p = 0.3755715613548539 (scipy 0.3755715613548539).
    const std::vector<double> a = over_24({8, 0, 6, 0, 2, 8, 0, 0, 0, 8, 3, 0, 12, 1, 2, 8, 2, 4, 0, 0});
    const std::vector<double> b = over_24({2, 2, 2, 2, 0, 0, 0, 0, 8, 0, 8, 0, 2, 8, 0, 3, 0, 0, 3, 0});
    const MannWhitney r = mann_whitney_u(a, b);
    CHECK(r.u == 231.5);
    CHECK(r.p == Approx(0.3755715613548539).epsilon(kRel));
    CHECK(r.method == Method::asymptotic);
    check_swap(a, b);
}

TEST_CASE("mann_whitney_u: 8 against 20 without ties is exact", "[stats]") {
    // oracle.py: U = 53, p = 0.18160519030084246, enumeration of all
    // C(28, 8) = 3108105 assignments (scipy 0.1816051903008425).
    const std::vector<double> a{0.147, 0.543, 0.027, 0.528, 0.979, 0.863, 0.696, 0.261};
    const std::vector<double> b{0.567, 0.367, 0.972, 0.733, 0.981, 0.53,  0.423, 1.012, 1.185, 1.053,
                                1.006, 1.018, 0.94,  0.427, 0.718, 0.556, 0.229, 0.228, 0.479, 0.459};
    const MannWhitney r = mann_whitney_u(a, b);
    CHECK(r.u == 53.0);
    CHECK(r.p == Approx(0.18160519030084246).epsilon(kRel));
    CHECK(r.method == Method::exact);
    check_swap(a, b);
}

TEST_CASE("mann_whitney_u: the exact rule stops at a sample of 8", "[stats]") {
    // 8 vs 9: exact, U = 0 + 0 + 1 + 1 + 2 + 2 + 3 + 3 = 12, p = 0.02064993829699712
    // (oracle.py, enumeration of C(17, 8) = 24310; scipy the same).
    // 9 vs 9 (9.5 added, it beats 3 5 7 9): U = 16, asymptotic, p = 0.03406919514414396
    // (oracle.py; scipy 0.034069195144143936).
    std::vector<double> a{1.5, 2.5, 3.5, 4.5, 5.5, 6.5, 7.5, 8.5};
    const std::vector<double> b{3, 5, 7, 9, 10, 11, 12, 13, 14};
    const MannWhitney eight = mann_whitney_u(a, b);
    CHECK(eight.u == 12.0);
    CHECK(eight.p == Approx(0.02064993829699712).epsilon(kRel));
    CHECK(eight.method == Method::exact);
    check_swap(a, b);

    a.push_back(9.5);
    const MannWhitney nine = mann_whitney_u(a, b);
    CHECK(nine.u == 16.0);
    CHECK(nine.p == Approx(0.03406919514414396).epsilon(kRel));
    CHECK(nine.method == Method::asymptotic);
    check_swap(a, b);
}

TEST_CASE("mann_whitney_u: a tie inside one small sample switches to the approximation", "[stats]") {
    const std::vector<double> a{1, 1, 5};
    const std::vector<double> b{2, 3, 4};
    CHECK(mann_whitney_u(a, b).method == Method::asymptotic);
    const std::vector<double> c{1, 6, 5};
    CHECK(mann_whitney_u(c, b).method == Method::exact);
}

TEST_CASE("mann_whitney_u: identical samples give p = 1", "[stats]") {
    // U_a = mn / 2 whatever the method: the two-sided p is capped at 1
    const std::vector<double> small{1, 2, 3};
    const MannWhitney r = mann_whitney_u(small, small);
    CHECK(r.u == 4.5);
    CHECK(r.p == 1.0);

    // no ties across the samples but U = mn / 2 on the exact path:
    // 2 P(U >= 2) = 2 (1 - P(U <= 1)) = 2 (1 - 2 / 6) > 1
    const std::vector<double> a{1, 4};
    const std::vector<double> b{2, 3};
    const MannWhitney e = mann_whitney_u(a, b);
    CHECK(e.u == 2.0);
    CHECK(e.p == 1.0);
    CHECK(e.method == Method::exact);

    std::vector<double> big;
    for (int i = 0; i < 20; ++i) big.push_back(i * 0.5);
    const MannWhitney g = mann_whitney_u(big, big);
    CHECK(g.u == 200.0);
    CHECK(g.p == 1.0);
    CHECK(g.method == Method::asymptotic);
}

TEST_CASE("mann_whitney_u: all values equal gives p = 1", "[stats]") {
    // sigma^2 = mn / 12 * ((n + 1) - (n^3 - n) / (n (n - 1))) = 0
    const std::vector<double> a{5, 5, 5};
    const std::vector<double> b{5, 5};
    const MannWhitney r = mann_whitney_u(a, b);
    CHECK(r.u == 3.0);
    CHECK(r.p == 1.0);
    CHECK(r.method == Method::asymptotic);

    const std::vector<double> one{0.0};
    const std::vector<double> minus_zero{-0.0};
    CHECK(mann_whitney_u(one, minus_zero).p == 1.0);
}

TEST_CASE("mann_whitney_u: infinities are ordinary values", "[stats]") {
    const double inf = std::numeric_limits<double>::infinity();
    const std::vector<double> a{inf, 3};
    const std::vector<double> b{-inf, 1, 2};
    // every a beats every b: U = 6, p = 2 / C(5, 2) = 0.2 as for {1, 2} vs {3, 4, 5}
    const MannWhitney r = mann_whitney_u(a, b);
    CHECK(r.u == 6.0);
    CHECK(r.p == Approx(0.2).epsilon(kRel));
}

TEST_CASE("mann_whitney_u: bad input throws DataError", "[stats]") {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const std::vector<double> empty;
    const std::vector<double> ok{1, 2};
    const std::vector<double> with_nan{1, nan};
    CHECK_THROWS_AS(mann_whitney_u(empty, ok), DataError);
    CHECK_THROWS_AS(mann_whitney_u(ok, empty), DataError);
    CHECK_THROWS_AS(mann_whitney_u(with_nan, ok), DataError);
    CHECK_THROWS_AS(mann_whitney_u(ok, with_nan), DataError);
    CHECK_THROWS_WITH(mann_whitney_u(ok, with_nan), "mann_whitney_u: sample b holds NaN at index 1");
    CHECK_THROWS_AS(mann_whitney_exact_cdf(0, 3, 1), DataError);
}

TEST_CASE("mann_whitney_exact_cdf: critical values of the published U tables", "[stats]") {
    // Two-sided 5% critical values of Mann-Whitney U tables: 13 for 8/8, 23 for
    // 10/10, 127 for 20/20, i.e. P(U <= c) <= 0.025 < P(U <= c + 1).
    // Exact fractions from oracle.py (enumeration, Gaussian binomial for 20/20).
    CHECK(mann_whitney_exact_cdf(8, 8, 13) == Approx(107.0 / 4290.0).epsilon(kRel));
    CHECK(mann_whitney_exact_cdf(8, 8, 14) == Approx(19.0 / 585.0).epsilon(kRel));
    CHECK(mann_whitney_exact_cdf(10, 10, 23) == Approx(999.0 / 46189.0).epsilon(kRel));
    CHECK(mann_whitney_exact_cdf(10, 10, 24) == Approx(4843.0 / 184756.0).epsilon(kRel));
    CHECK(mann_whitney_exact_cdf(20, 20, 127) == Approx(53705801.0 / 2188040140.0).epsilon(kRel));
    CHECK(mann_whitney_exact_cdf(20, 20, 128) == Approx(3611546101.0 / 137846528820.0).epsilon(kRel));
    CHECK(mann_whitney_exact_cdf(20, 20, 127) <= 0.025);
    CHECK(mann_whitney_exact_cdf(20, 20, 128) > 0.025);
}

TEST_CASE("mann_whitney_exact_cdf: 50 against 50 without overflow", "[stats]") {
    // oracle.py, exact integer coefficients of [100 choose 50]_q:
    // P(U <= 0) = 1 / C(100, 50) = 1 / 100891344545564193334812497256
    CHECK(mann_whitney_exact_cdf(50, 50, 0) == Approx(9.911653021418339e-30).epsilon(kRel));
    CHECK(mann_whitney_exact_cdf(50, 50, 900) == Approx(0.007761972615356092).epsilon(kRel));
    CHECK(mann_whitney_exact_cdf(50, 50, 1100) == Approx(0.15206980726517322).epsilon(kRel));
    CHECK(mann_whitney_exact_cdf(50, 50, 1249) == Approx(0.49863110449923614).epsilon(kRel));
    // symmetry: P(U <= k) + P(U <= mn - k - 1) = 1
    CHECK(mann_whitney_exact_cdf(50, 50, 1249) + mann_whitney_exact_cdf(50, 50, 1250) ==
          Approx(1.0).epsilon(kRel));
    CHECK(mann_whitney_exact_cdf(50, 50, 2500) == 1.0);
    CHECK(mann_whitney_exact_cdf(50, 50, 100000) == 1.0);
}

TEST_CASE("mann_whitney_exact_cdf: unequal sizes in either order", "[stats]") {
    // oracle.py: 358 / 12341 by enumeration of C(43, 3) = 12341
    CHECK(mann_whitney_exact_cdf(3, 40, 20) == Approx(358.0 / 12341.0).epsilon(kRel));
    CHECK(mann_whitney_exact_cdf(40, 3, 20) == Approx(358.0 / 12341.0).epsilon(kRel));
    // 1 against n: U is uniform on 0..n
    CHECK(mann_whitney_exact_cdf(1, 9, 3) == Approx(0.4).epsilon(kRel));
}

TEST_CASE("vargha_delaney_a12: by hand", "[stats]") {
    // 3 beats 1 2 and ties 3: 2.5; 4 beats all three: 3; A12 = 5.5 / 6
    const std::vector<double> a{3, 4};
    const std::vector<double> b{1, 2, 3};
    CHECK(vargha_delaney_a12(a, b) == Approx(5.5 / 6.0).epsilon(kRel));
    CHECK(vargha_delaney_a12(b, a) == Approx(0.5 / 6.0).epsilon(kRel));
    // 1 loses twice, each 2 ties twice (0.5 each), 3 wins twice: 3 / 6
    const std::vector<double> c{1, 2, 3};
    const std::vector<double> d{2, 2};
    CHECK(vargha_delaney_a12(c, d) == 0.5);
    CHECK(vargha_delaney_a12(c, c) == 0.5);
    // equals U_a / (n_a n_b)
    const std::vector<double> males{19, 22, 16, 29, 24};
    const std::vector<double> females{20, 11, 17, 12};
    CHECK(vargha_delaney_a12(males, females) == Approx(17.0 / 20.0).epsilon(kRel));

    const std::vector<double> empty;
    const std::vector<double> with_nan{std::numeric_limits<double>::quiet_NaN()};
    CHECK_THROWS_AS(vargha_delaney_a12(empty, a), DataError);
    CHECK_THROWS_AS(vargha_delaney_a12(a, with_nan), DataError);
}

TEST_CASE("holm: R's p.adjust by hand", "[stats]") {
    // sorted 0.005 0.01 0.03 0.04 times 4 3 2 1: 0.02 0.03 0.06 0.04,
    // running max 0.02 0.03 0.06 0.06, back in input order:
    const std::vector<double> p{0.01, 0.04, 0.03, 0.005};
    const std::vector<double> h = holm(p);
    REQUIRE(h.size() == 4);
    CHECK(h[0] == Approx(0.03).epsilon(kRel));
    CHECK(h[1] == Approx(0.06).epsilon(kRel));
    CHECK(h[2] == Approx(0.06).epsilon(kRel));
    CHECK(h[3] == Approx(0.02).epsilon(kRel));

    // tied p-values: sorted 0.01 0.04 0.2 0.2 0.5 times 5 4 3 2 1:
    // 0.05 0.16 0.6 0.4 0.5, running max 0.05 0.16 0.6 0.6 0.6
    const std::vector<double> q{0.2, 0.01, 0.2, 0.5, 0.04};
    const std::vector<double> g = holm(q);
    REQUIRE(g.size() == 5);
    CHECK(g[0] == Approx(0.6).epsilon(kRel));
    CHECK(g[1] == Approx(0.05).epsilon(kRel));
    CHECK(g[2] == Approx(0.6).epsilon(kRel));
    CHECK(g[3] == Approx(0.6).epsilon(kRel));
    CHECK(g[4] == Approx(0.16).epsilon(kRel));

    // capped at 1: 2 * 0.6 = 1.2
    const std::vector<double> r{0.6, 0.7};
    CHECK(holm(r) == std::vector<double>{1.0, 1.0});
    // one p-value is left alone; none gives none
    const std::vector<double> single{0.03};
    CHECK(holm(single) == std::vector<double>{0.03});
    CHECK(holm(std::vector<double>{}).empty());
}

TEST_CASE("holm: p-values outside 0..1 throw DataError", "[stats]") {
    CHECK_THROWS_AS(holm(std::vector<double>{0.1, -0.01}), DataError);
    CHECK_THROWS_AS(holm(std::vector<double>{1.5}), DataError);
    CHECK_THROWS_AS(holm(std::vector<double>{std::numeric_limits<double>::quiet_NaN()}), DataError);
    CHECK_NOTHROW(holm(std::vector<double>{0.0, 1.0}));
}
