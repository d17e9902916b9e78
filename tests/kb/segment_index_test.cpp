#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <vector>

#include "core/error.hpp"
#include "core/rng.hpp"
#include "kb/block_means.hpp"
#include "kb/bound_tree.hpp"
#include "kb/distance.hpp"
#include "kb/projection.hpp"
#include "kb/segment_index.hpp"
#include "oracle.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;

namespace {

// the nearest with squared distance < r^2, by linear scan (ties: lowest id)
std::optional<std::pair<std::size_t, double>> oracle_within(const std::vector<float>& values, std::size_t dim,
                                                            const float* q, double r) {
    auto best = kboracle::oracle_nearest(values, dim, q);
    if (best && best->second < r * r) return best;
    return std::nullopt;
}

void check_queries(kb::SegmentIndex& index, const std::vector<float>& values, const std::vector<float>& queries,
                   double radius) {
    const std::size_t dim = index.dim();
    // all queries at once (interleaved tree walks or one brute-force pass),
    // before the adaptive queries below can change the path
    const std::size_t count = queries.size() / dim;
    std::vector<std::optional<kb::Neighbour>> batch(count);
    index.nearest_within_batch(values, queries.data(), count, radius, batch);
    for (std::size_t i = 0; i < count; ++i) {
        const auto expect = oracle_within(values, dim, queries.data() + i * dim, radius);
        REQUIRE(batch[i].has_value() == expect.has_value());
        if (expect) {
            REQUIRE(batch[i]->id == expect->first);
            REQUIRE(batch[i]->squared_distance == expect->second);
        }
    }
    for (std::size_t i = 0; i * dim < queries.size(); ++i) {
        const float* q = queries.data() + i * dim;
        const auto expect = oracle_within(values, dim, q, radius);
        const auto got = index.nearest_within(values, q, radius);
        const auto got_adaptive = index.nearest_within_adaptive(values, q, radius);
        REQUIRE(got.has_value() == expect.has_value());
        REQUIRE(got_adaptive.has_value() == expect.has_value());
        if (expect) {
            REQUIRE(got->id == expect->first);
            REQUIRE(got->squared_distance == expect->second);
            REQUIRE(got_adaptive->id == expect->first);
        }
        const auto nearest = index.nearest(values, q);
        const auto expect_nearest = kboracle::oracle_nearest(values, dim, q);
        REQUIRE(nearest.has_value() == expect_nearest.has_value());
        if (expect_nearest) {
            REQUIRE(nearest->id == expect_nearest->first);
            REQUIRE(nearest->squared_distance == expect_nearest->second);
        }
    }
}

// behaviour-like segments: `channels` channels of `width` rows cut from long
// series, half of them smooth (random walks in [0, 1]) and half binary,
// switching rarely; series are shared by families with small offsets, so
// many segments lie near each other as the behaviours of one run do
std::vector<float> behaviour_segments(Rng& rng, std::size_t n, std::size_t width, std::size_t channels) {
    constexpr std::size_t kFamilies = 6;
    const std::size_t steps = n * width / kFamilies + width;
    std::vector<float> series(kFamilies * steps * channels);
    for (std::size_t f = 0; f < kFamilies; ++f)
        for (std::size_t c = 0; c < channels; ++c) {
            double v = rng.uniform();
            for (std::size_t t = 0; t < steps; ++t) {
                if (c % 2 == 0) {
                    v = std::clamp(v + rng.uniform(-0.05, 0.05), 0.0, 1.0);
                    series[(f * steps + t) * channels + c] = static_cast<float>(v);
                } else {
                    if (rng.bernoulli(0.02)) v = v < 0.5 ? 1.0 : 0.0;
                    series[(f * steps + t) * channels + c] = v < 0.5 ? 0.0f : 1.0f;
                }
            }
        }
    std::vector<float> out(n * width * channels);
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t f = static_cast<std::size_t>(rng.below(kFamilies));
        const std::size_t start = static_cast<std::size_t>(rng.below(steps - width));
        const float offset = static_cast<float>(rng.uniform(-0.03, 0.03));
        for (std::size_t k = 0; k < width * channels; ++k) {
            const float v = series[(f * steps + start) * channels + k];
            out[i * width * channels + k] = (k % channels) % 2 == 0 ? v + offset : v;
        }
    }
    return out;
}

}  // namespace

TEST_CASE("block means never exceed the distance, and more blocks bound it more tightly", "[kb][index][bound]") {
    Rng rng(12, 0, 0, Purpose::test);
    struct Shape {
        std::size_t width, channels;
    };
    for (const Shape s : {Shape{20, 15}, Shape{7, 3}, Shape{1, 4}, Shape{13, 1}}) {
        const std::size_t dim = s.width * s.channels;
        CAPTURE(s.width, s.channels);
        const std::vector<float> v = kboracle::uniform_segments(rng, 400, dim);
        for (std::size_t blocks : {1u, 2u, 3u, 5u, 20u}) {
            const kb::BlockMeans means(s.width, s.channels, blocks);
            CHECK(means.blocks() == std::min<std::size_t>(blocks, s.width));
            std::vector<double> a(means.dim()), b(means.dim());
            for (std::size_t i = 0; i + 1 < 400; i += 2) {
                means.point(v.data() + i * dim, a.data());
                means.point(v.data() + (i + 1) * dim, b.data());
                const double bound = kb::squared_gap(a.data(), b.data(), means.dim());
                const double d2 = kb::squared_distance(v.data() + i * dim, v.data() + (i + 1) * dim, dim);
                REQUIRE(bound <= d2 * (1 + 1e-12));
                // with one row per block the point is the segment itself
                if (means.blocks() == s.width) REQUIRE(bound == Approx(d2).epsilon(1e-12));
            }
        }
        // nested blocks: 2 blocks never bound more loosely than 1 where 1 | 2
        const kb::BlockMeans one(s.width, s.channels, 1), two(s.width, s.channels, 2);
        std::vector<double> a1(one.dim()), b1(one.dim()), a2(two.dim()), b2(two.dim());
        for (std::size_t i = 0; i + 1 < 400; i += 2) {
            one.point(v.data() + i * dim, a1.data());
            one.point(v.data() + (i + 1) * dim, b1.data());
            two.point(v.data() + i * dim, a2.data());
            two.point(v.data() + (i + 1) * dim, b2.data());
            REQUIRE(kb::squared_gap(a1.data(), b1.data(), one.dim()) <=
                    kb::squared_gap(a2.data(), b2.data(), two.dim()) * (1 + 1e-12) + 1e-300);
        }
    }
}

TEST_CASE("a projection keeps a lower bound: orthonormal rows never lengthen a difference", "[kb][index][bound]") {
    Rng rng(13, 0, 0, Purpose::test);
    const std::size_t width = 20, channels = 15;
    const kb::BlockMeans means(width, channels, 5);
    const std::vector<float> segments = behaviour_segments(rng, 600, width, channels);
    std::vector<float> points(600 * means.dim());
    std::vector<double> p(means.dim());
    for (std::size_t i = 0; i < 600; ++i) {
        means.point(segments.data() + i * width * channels, p.data());
        for (std::size_t k = 0; k < means.dim(); ++k) points[i * means.dim() + k] = static_cast<float>(p[k]);
    }
    const kb::Projection fallback = kb::Projection::channel_means(width, channels, 5);
    CHECK(fallback.orthonormality_error() < 1e-15);
    const kb::Projection principal = kb::Projection::principal(points.data(), 600, means.dim(), 12, fallback);
    CHECK(principal.out_dim() == 12);
    CHECK(principal.orthonormality_error() < 1e-12);
    for (const kb::Projection* proj : {&fallback, &principal}) {
        std::vector<double> a(proj->out_dim()), b(proj->out_dim());
        for (std::size_t i = 0; i + 1 < 600; i += 2) {
            proj->apply(points.data() + i * means.dim(), a.data());
            proj->apply(points.data() + (i + 1) * means.dim(), b.data());
            double full = 0;
            for (std::size_t k = 0; k < means.dim(); ++k) {
                const double d = static_cast<double>(points[i * means.dim() + k]) - points[(i + 1) * means.dim() + k];
                full += d * d;
            }
            REQUIRE(kb::squared_gap(a.data(), b.data(), proj->out_dim()) <= full * (1 + 1e-12) + 1e-300);
        }
    }
    // the channel-means projection of the block means is the channel means
    std::vector<double> direct(channels), projected(channels);
    kb::BlockMeans(width, channels, 1).point(segments.data(), direct.data());
    means.point(segments.data(), p.data());
    fallback.apply(p.data(), projected.data());
    for (std::size_t c = 0; c < channels; ++c) CHECK(projected[c] == Approx(direct[c]).epsilon(1e-12));
}

TEST_CASE("block means and projections add their terms in the documented order, bit for bit", "[kb][index][bound]") {
    // the bounds' padding assumes these sums: a block's values added row by
    // row to 0.0 then scaled by 1 / sqrt(rows); a projected coordinate as
    // four partial sums over k = j (mod 4), then (s0 + s1) + (s2 + s3). The
    // kernels vectorise them differently (by channels, by outputs), so any
    // reordering shows here as different bits
    Rng rng(21, 0, 0, Purpose::test);
    for (const std::size_t channels : {1, 2, 3, 4, 5, 7, 15, 16}) {
        for (const std::size_t width : {1, 4, 20, 23}) {
            const kb::BlockMeans means(width, channels, 5);
            const std::vector<float> segment = behaviour_segments(rng, 1, width, channels);
            std::vector<double> got(means.dim());
            means.point(segment.data(), got.data());
            for (std::size_t b = 0; b < means.blocks(); ++b) {
                const std::size_t first = b * width / means.blocks(), end = (b + 1) * width / means.blocks();
                for (std::size_t c = 0; c < channels; ++c) {
                    double sum = 0.0;
                    for (std::size_t t = first; t < end; ++t) sum += static_cast<double>(segment[t * channels + c]);
                    const double expected = sum * (1.0 / std::sqrt(static_cast<double>(end - first)));
                    REQUIRE(got[b * channels + c] == expected);
                }
            }
        }
    }
    const std::size_t in = 75;
    std::vector<float> points(300 * in);
    for (float& v : points) v = static_cast<float>(rng.uniform(-3.0, 3.0));
    const kb::Projection fallback = kb::Projection::channel_means(20, 15, 5);
    for (const std::size_t out : {1, 4, 5, 9, 12, 15, 20, 29}) {
        const kb::Projection proj = kb::Projection::principal(points.data(), 300, in, out, fallback);
        REQUIRE(proj.out_dim() == out);
        // the rows, read back through unit vectors (a single term is exact)
        std::vector<double> rows(out * in), unit(in, 0.0), column(out);
        for (std::size_t k = 0; k < in; ++k) {
            unit[k] = 1.0;
            proj.apply(unit.data(), column.data());
            unit[k] = 0.0;
            for (std::size_t r = 0; r < out; ++r) rows[r * in + k] = column[r];
        }
        std::vector<double> got(out);
        for (std::size_t i = 0; i < 20; ++i) {
            const float* x = points.data() + i * in;
            proj.apply(x, got.data());
            for (std::size_t r = 0; r < out; ++r) {
                double s[4] = {};
                for (std::size_t k = 0; k < in; ++k) s[k % 4] += rows[r * in + k] * static_cast<double>(x[k]);
                REQUIRE(got[r] == (s[0] + s[1]) + (s[2] + s[3]));
            }
        }
    }
}

TEST_CASE("the tree walk runs its AVX2 build only where the CPU has it and STEPSTONE_KB_GENERIC is unset", "[kb][index]") {
    // ctest runs this binary twice, the second time with STEPSTONE_KB_GENERIC=1,
    // so that every index test also covers the generic build of the walk
    std::vector<float> points(40 * 4);
    for (std::size_t i = 0; i < points.size(); ++i) points[i] = static_cast<float>(i % 7);
    const kb::BoundTree tree(points.data(), 4, 4, 0, 40, 16);
#if defined(__x86_64__) || defined(__i386__)
    const bool cpu = __builtin_cpu_supports("avx2");
#else
    const bool cpu = false;
#endif
    CHECK(tree.avx2() == (cpu && std::getenv("STEPSTONE_KB_GENERIC") == nullptr));
}

TEST_CASE("the index equals a linear scan on behaviour-like data, bulk-built and grown", "[kb][index]") {
    // past the size where the projection is fitted to the data, with near
    // duplicates, binary channels and queries both near and far from the KB
    Rng rng(14, 0, 0, Purpose::test);
    const std::size_t width = 20, channels = 15, dim = width * channels;
    const std::vector<float> data = behaviour_segments(rng, 2600, width, channels);
    std::vector<float> queries = behaviour_segments(rng, 30, width, channels);
    const std::vector<float> far = kboracle::uniform_segments(rng, 5, dim);
    queries.insert(queries.end(), far.begin(), far.end());
    for (const double radius : {0.8, 1.83, 3.0}) {
        CAPTURE(radius);
        kb::SegmentIndex grown(width, channels);
        std::vector<float> values;
        for (std::size_t i = 0; i < 2600; ++i) {
            values.insert(values.end(), data.begin() + static_cast<std::ptrdiff_t>(i * dim),
                          data.begin() + static_cast<std::ptrdiff_t>((i + 1) * dim));
            grown.append(values.data() + i * dim);
            if (i == 1100 || i == 2047 || i == 2599) check_queries(grown, values, queries, radius);
        }
        CHECK_FALSE(grown.brute_force());
        kb::SegmentIndex bulk(width, channels);
        bulk.assign(values);
        check_queries(bulk, values, queries, radius);
        // stored segments as queries: distance 0, the lowest id among equals
        check_queries(bulk, values, std::vector<float>(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(40 * dim)), radius);
    }
}

TEST_CASE("values too large for float bounds send the index to brute force, still exact", "[kb][index]") {
    Rng rng(15, 0, 0, Purpose::test);
    const std::size_t width = 4, channels = 3, dim = width * channels;
    std::vector<float> values = kboracle::clustered_segments(rng, 300, dim, 10, 0.1);
    for (std::size_t k = 0; k < dim; ++k) values[150 * dim + k] = 1e30f;
    kb::SegmentIndex index(width, channels);
    for (std::size_t i = 0; i < 300; ++i) index.append(values.data() + i * dim);
    CHECK(index.brute_force());
    const std::vector<float> queries = kboracle::clustered_segments(rng, 10, dim, 10, 0.1);
    check_queries(index, values, queries, 0.5);
}

TEST_CASE("the distance follows the documented lane order", "[kb][distance]") {
    // the oracle writes the documented order as a plain loop
    Rng rng(3, 0, 0, Purpose::test);
    for (std::size_t dim : {1u, 2u, 7u, 8u, 9u, 31u, 32u, 33u, 300u}) {
        const std::vector<float> v = kboracle::uniform_segments(rng, 2, dim);
        const double expect = kboracle::oracle_squared_distance(v.data(), v.data() + dim, dim);
        CHECK(kb::squared_distance(v.data(), v.data() + dim, dim) == expect);
        // with a bound above the distance the value is exact, below it the result exceeds the bound
        CHECK(kb::squared_distance_up_to(v.data(), v.data() + dim, dim, expect) == expect);
        CHECK(kb::squared_distance_up_to(v.data(), v.data() + dim, dim, expect * 0.5) > expect * 0.5);
    }
    // by hand: (0,0,0) to (1,2,2) is 9
    const float a[3] = {0, 0, 0}, b[3] = {1, 2, 2};
    CHECK(kb::squared_distance(a, b, 3) == 9.0);
    // lanes whose sums differ so much that another lane for a value, or another pairing of the
    // lanes, rounds differently: 2^53 in one lane (two squares of 2^26), 1 in the next two
    for (std::size_t dim : {16u, 21u, 300u}) {
        for (std::size_t big = 0; big < kb::kDistanceLanes; ++big) {
            std::vector<float> x(dim, 0.0f);
            const std::vector<float> zero(dim, 0.0f);
            x[big] = x[big + 8] = 67108864.0f;  // 2^26
            for (std::size_t k = 0; k < dim; ++k) {
                if (k % kb::kDistanceLanes == (big + 1) % kb::kDistanceLanes && k < 8) x[k] = 1.0f;
                if (k % kb::kDistanceLanes == (big + 2) % kb::kDistanceLanes && k >= 16) x[k] = 1.0f;
            }
            CAPTURE(dim, big);
            const double expect = kboracle::oracle_squared_distance(x.data(), zero.data(), dim);
            CHECK(kb::squared_distance(x.data(), zero.data(), dim) == expect);
            CHECK(kb::squared_distance_up_to(x.data(), zero.data(), dim, expect) == expect);
        }
    }
}

TEST_CASE("the index equals a linear scan after many inserts and rebuilds", "[kb][index]") {
    // clustered data prunes well (tree path), uniform data in 300-D does not
    // (brute-force path); both must give the linear scan's answers
    struct Setup {
        std::size_t width, channels;
        int kind;
        double radius;
    };
    const Setup setups[] = {{1, 2, 1, 0.3}, {5, 3, 1, 1.0}, {20, 15, 1, 2.5}, {20, 15, 0, 7.0}, {4, 3, 2, 0.5}};
    for (const Setup s : setups) {
        const std::size_t dim = s.width * s.channels;
        CAPTURE(dim, s.kind);
        Rng rng(41, dim, static_cast<std::uint64_t>(s.kind), Purpose::test);
        const std::size_t n = dim >= 300 ? 1500 : 3000;
        const std::vector<float> data = s.kind == 0   ? kboracle::uniform_segments(rng, n, dim)
                                        : s.kind == 1 ? kboracle::clustered_segments(rng, n, dim, 30, 0.2)
                                                      : kboracle::grid_segments(rng, n, dim, 3);
        kb::SegmentIndex index(s.width, s.channels);
        std::vector<float> values;
        const std::vector<float> queries = s.kind == 0   ? kboracle::uniform_segments(rng, 12, dim)
                                           : s.kind == 1 ? kboracle::clustered_segments(rng, 12, dim, 30, 0.3)
                                                         : kboracle::grid_segments(rng, 12, dim, 3);
        for (std::size_t i = 0; i < n; ++i) {
            values.insert(values.end(), data.begin() + static_cast<std::ptrdiff_t>(i * dim),
                          data.begin() + static_cast<std::ptrdiff_t>((i + 1) * dim));
            index.append(values.data() + i * dim);
            // check around buffer flushes and at irregular sizes
            if (i % 97 == 0 || i % 64 == 63 || i % 64 == 0) check_queries(index, values, queries, s.radius);
        }
        CHECK(index.size() == n);
        CHECK(index.stats().rebuilds > 5);
        // a bulk-built index gives the same answers
        kb::SegmentIndex bulk(s.width, s.channels);
        bulk.assign(values);
        check_queries(bulk, values, queries, s.radius);
        // existing segments as queries: distance 0, lowest id among duplicates
        check_queries(index, values, std::vector<float>(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(20 * dim)), s.radius);
    }
}

TEST_CASE("the index falls back to brute force when the lower bounds prune nothing", "[kb][index]") {
    // uniform values in 300-D: channel means all lie near 1/2, so most of the
    // KB passes the lower bound for a radius of 7 (typical distances ~7)
    Rng rng(8, 0, 0, Purpose::test);
    const std::size_t dim = 300;
    const std::vector<float> values = kboracle::uniform_segments(rng, 800, dim);
    kb::SegmentIndex index(20, 15);
    index.assign(values);
    const std::vector<float> queries = kboracle::uniform_segments(rng, 200, dim);
    for (std::size_t i = 0; i < 200; ++i) index.nearest_within_adaptive(values, queries.data() + i * dim, 7.0);
    CHECK(index.brute_force());
    CHECK(index.stats().linear_queries > 0);
    // clustered data with a small radius stays on the trees
    const std::vector<float> clustered = kboracle::clustered_segments(rng, 800, dim, 40, 0.05);
    kb::SegmentIndex tree(20, 15);
    tree.assign(clustered);
    for (std::size_t i = 0; i < 200; ++i) tree.nearest_within_adaptive(clustered, clustered.data() + i * dim, 1.0);
    CHECK_FALSE(tree.brute_force());
    CHECK(tree.stats().linear_queries == 0);
}

TEST_CASE("an index needs a width and channels", "[kb][index][errors]") {
    REQUIRE_THROWS_WITH(kb::SegmentIndex(0, 3), Contains("segment_width must be >= 1, got 0"));
    REQUIRE_THROWS_WITH(kb::SegmentIndex(3, 0), Contains("channels must be >= 1, got 0"));
    kb::SegmentIndex empty(2, 2);
    const float q[4] = {0, 0, 0, 0};
    CHECK_FALSE(empty.nearest({}, q).has_value());
    CHECK_FALSE(empty.nearest_within({}, q, 1.0).has_value());
}
