#include "kb/signature_scan.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

#include "core/rng.hpp"
#include "oracle.hpp"

using namespace stepstone;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

kb::SignatureScan scan_of(const std::vector<float>& values, std::size_t width, std::size_t channels,
                          std::vector<std::size_t> binary) {
    kb::SignatureScan scan(width, channels, std::move(binary));
    const std::size_t dim = width * channels;
    for (std::size_t k = 0; k * dim < values.size(); ++k) scan.add(values.data() + k * dim);
    return scan;
}

// the answer by definition: the first segment (lowest index) of smallest
// squared distance among those < radius_sq and <= worst
std::optional<std::pair<std::size_t, double>> oracle(const std::vector<float>& values, std::size_t dim,
                                                     const float* query, double radius_sq, double worst) {
    std::optional<std::pair<std::size_t, double>> best;
    for (std::size_t k = 0; k * dim < values.size(); ++k) {
        const double d2 = kboracle::oracle_squared_distance(query, values.data() + k * dim, dim);
        if (d2 < radius_sq && d2 <= worst && (!best || d2 < best->second)) best = std::make_pair(k, d2);
    }
    return best;
}

void require_same(const kb::SignatureScan& scan, const std::vector<float>& values, const float* query,
                  double radius_sq, double worst) {
    const auto got = scan.nearest(scan.prepare(query, 1)[0], values.data(), radius_sq, worst);
    const auto want = oracle(values, scan.dim(), query, radius_sq, worst);
    REQUIRE(got.has_value() == want.has_value());
    if (want) {
        REQUIRE(got->id == want->first);
        REQUIRE(got->squared_distance == want->second);
    }
}

}  // namespace

TEST_CASE("binary channels are those holding only 0 and 1 in every segment", "[kb][signature]") {
    // 2 rows x 4 channels: channel 0 holds 0/1, channel 1 a 0.5, channel 2
    // 1 and -0.0 (equal to 0), channel 3 a 2
    const std::vector<float> values{1, 0, 1, 0, 0, 0.5f, -0.0f, 1,   // segment 0
                                    0, 1, 1, 2, 1, 0,    0,     0};  // segment 1
    CHECK(kb::SignatureScan::binary_channels(values, 2, 4) == std::vector<std::size_t>{0, 2});
    // the first segment alone: channel 3 holds 0 and 1 too
    CHECK(kb::SignatureScan::binary_channels(std::span<const float>(values).first(8), 2, 4) ==
          std::vector<std::size_t>{0, 2, 3});
}

TEST_CASE("a segment whose distance is exactly its Hamming distance is found just inside the radius",
          "[kb][signature]") {
    // by hand, 4 rows x 2 channels (channel 0 binary, channel 1 not): the
    // query differs from segment 1 in three bits of channel 0 (counts 0 and
    // 3: L1 = H = 3) and equals it elsewhere, so its squared distance is 3
    // exactly; segment 0 is far in channel 1
    const std::vector<float> values{0, 9,     0, 9,    0, 9,     0, 9,  // segment 0
                                    1, 0.25f, 1, 0.5f, 1, 0.75f, 0, 1};
    const std::vector<float> query{0, 0.25f, 0, 0.5f, 0, 0.75f, 0, 1};
    const auto scan = scan_of(values, 4, 2, {0});
    const auto prepared = scan.prepare(query.data(), 1);
    const auto q = prepared[0];
    // within 1.83 (3 < 3.3489), not within sqrt(3) (3 < 3 fails)
    const auto near = scan.nearest(q, values.data(), 1.83 * 1.83, kInf);
    REQUIRE(near);
    CHECK(near->id == 1);
    CHECK(near->squared_distance == 3.0);
    CHECK_FALSE(scan.nearest(q, values.data(), 3.0, kInf));
    CHECK(scan.nearest(q, values.data(), std::nextafter(3.0, 4.0), kInf));
    // `worst` keeps an equal distance and drops a larger one
    CHECK(scan.nearest(q, values.data(), kInf, 3.0));
    CHECK_FALSE(scan.nearest(q, values.data(), kInf, std::nextafter(3.0, 0.0)));
    // whatever the distance: segment 1 (segment 0 is 4 x 81 + ... away)
    CHECK(scan.nearest(q, values.data(), kInf, kInf)->id == 1);
}

TEST_CASE("a scan answers as a linear scan on behaviour-like segments", "[kb][signature]") {
    // 20 rows x 6 channels, channels 1, 2 and 4 binary: the paper's shape
    const std::size_t width = 20, channels = 6, dim = width * channels;
    const std::vector<std::size_t> binary{1, 2, 4};
    for (const std::uint64_t seed : {1u, 2u}) {
        Rng rng(seed, 0, 0, Purpose::test);
        const auto values = kboracle::binary_segments(rng, 700, width, channels, binary, 30, 0.02, 0.05);
        REQUIRE(kb::SignatureScan::binary_channels(values, width, channels) == binary);
        const auto scan = scan_of(values, width, channels, binary);
        const auto queries = kboracle::binary_segments(rng, 60, width, channels, binary, 30, 0.03, 0.08);
        for (std::size_t i = 0; i < 60; ++i) {
            const float* q = queries.data() + i * dim;
            for (const double radius : {0.5, 1.83, 3.84, 8.0})
                require_same(scan, values, q, radius * radius, kInf);
            require_same(scan, values, q, kInf, kInf);
            // a worst from elsewhere: the oracle's own best distance (ties
            // kept) and just below it
            const auto best = oracle(values, dim, q, kInf, kInf);
            require_same(scan, values, q, kInf, best->second);
            require_same(scan, values, q, 3.84 * 3.84, std::nextafter(best->second, 0.0));
        }
    }
}

TEST_CASE("a scan keeps the lowest index among equal distances", "[kb][signature]") {
    const std::size_t width = 20, channels = 6, dim = width * channels;
    const std::vector<std::size_t> binary{1, 2, 4};
    Rng rng(5, 0, 0, Purpose::test);
    // every segment three times, the copies 40 and 80 places later
    auto values = kboracle::binary_segments(rng, 40, width, channels, binary, 5, 0.05, 0.05);
    const std::vector<float> once = values;
    values.insert(values.end(), once.begin(), once.end());
    values.insert(values.end(), once.begin(), once.end());
    const auto scan = scan_of(values, width, channels, binary);
    for (std::size_t i = 0; i < 40; ++i) {
        std::vector<float> q(once.begin() + static_cast<std::ptrdiff_t>(i * dim),
                             once.begin() + static_cast<std::ptrdiff_t>((i + 1) * dim));
        // off the segment in floats only: the three copies tie, and only
        // their full distances can tell
        q[0] += 0.01f;
        q[5] -= 0.02f;
        require_same(scan, values, q.data(), 4.0, kInf);
        REQUIRE(scan.nearest(scan.prepare(q.data(), 1)[0], values.data(), 4.0, kInf)->id == i);
        const auto near = scan.nearest(scan.prepare(once.data() + i * dim, 1)[0], values.data(), 1.0, kInf);
        REQUIRE(near);
        CHECK(near->id == i);
        CHECK(near->squared_distance == 0.0);
    }
}

TEST_CASE("a query with other values in a binary channel is answered exactly without its bounds",
          "[kb][signature]") {
    const std::size_t width = 20, channels = 6, dim = width * channels;
    const std::vector<std::size_t> binary{1, 2, 4};
    Rng rng(9, 0, 0, Purpose::test);
    const auto values = kboracle::binary_segments(rng, 500, width, channels, binary, 20, 0.02, 0.05);
    const auto scan = scan_of(values, width, channels, binary);
    auto queries = kboracle::binary_segments(rng, 30, width, channels, binary, 20, 0.02, 0.05);
    for (std::size_t i = 0; i < 30; ++i) {
        float* q = queries.data() + i * dim;
        q[(i % width) * channels + binary[i % 3]] = 0.4f;  // one value off {0, 1}
        if (i % 2 == 0) q[channels + 2] = -1.0f;
        for (const double radius : {0.5, 1.83, 3.84}) require_same(scan, values, q, radius * radius, kInf);
        require_same(scan, values, q, kInf, kInf);
    }
}

TEST_CASE("a scan stays exact without counts, without binary channels and at large magnitudes",
          "[kb][signature]") {
    Rng rng(11, 0, 0, Purpose::test);
    SECTION("64 rows x 4 binary channels: the counts' L1 could pass 255, the counts' stage is off") {
        const std::size_t width = 64, channels = 5;
        const std::vector<std::size_t> binary{0, 1, 2, 3};
        const auto values = kboracle::binary_segments(rng, 300, width, channels, binary, 10, 0.02, 0.05);
        const auto scan = scan_of(values, width, channels, binary);
        CHECK(scan.bytes_per_segment() == 4 * sizeof(std::uint64_t) + 16 * sizeof(float));
        const auto queries = kboracle::binary_segments(rng, 20, width, channels, binary, 10, 0.03, 0.05);
        for (std::size_t i = 0; i < 20; ++i)
            for (const double r2 : {2.0, 9.0, 30.0, kInf})
                require_same(scan, values, queries.data() + i * width * channels, r2, kInf);
    }
    SECTION("no binary channel: the block sums alone") {
        const auto values = kboracle::clustered_segments(rng, 400, 3 * 4, 10, 0.3);
        const auto scan = scan_of(values, 3, 4, {});
        const auto queries = kboracle::clustered_segments(rng, 20, 3 * 4, 10, 0.4);
        for (std::size_t i = 0; i < 20; ++i)
            for (const double r2 : {0.1, 1.0, kInf})
                require_same(scan, values, queries.data() + i * 12, r2, kInf);
    }
    SECTION("continuous values near 1e20 and beyond 1e30") {
        const std::size_t width = 8, channels = 3;
        for (const double scale : {1e20, 1e33}) {
            auto values = kboracle::binary_segments(rng, 200, width, channels, {1}, 10, 0.05, 0.05);
            for (std::size_t i = 0; i < values.size(); ++i)
                if (i % channels != 1) values[i] = static_cast<float>(values[i] * scale);
            const auto scan = scan_of(values, width, channels, {1});
            for (std::size_t i = 0; i < 20; ++i) {
                std::vector<float> q(
                    values.begin() + static_cast<std::ptrdiff_t>(i * 7 * width * channels),
                    values.begin() + static_cast<std::ptrdiff_t>((i * 7 + 1) * width * channels));
                q[0] = static_cast<float>(q[0] * (1 + 1e-7));
                q[4] = 1.0f - q[4];
                for (const double r2 : {1.5, 2.5 * scale * scale, kInf})
                    require_same(scan, values, q.data(), r2, kInf);
            }
        }
    }
}

TEST_CASE("the block sums' bound allows for their rounding to float", "[kb][signature]") {
    // 4 rows x 2 channels (channel 0 binary). The float channel is near 1000
    // and the query moves each row by about the same small amount, so the
    // block-means bound is nearly the whole distance, while rounding the block
    // sums to float moves their difference by up to ~1e-4, more than the
    // distance itself: unpadded, the bound would exceed some distances and
    // drop segments lying just inside the radius
    Rng rng(13, 0, 0, Purpose::test);
    for (int trial = 0; trial < 400; ++trial) {
        std::vector<float> segment(8), query(8);
        const double step = rng.uniform(0.0005, 0.002);
        for (std::size_t r = 0; r < 4; ++r) {
            segment[r * 2] = query[r * 2] = static_cast<float>(rng.below(2));
            segment[r * 2 + 1] = static_cast<float>(1000.0 + rng.uniform(-1.0, 1.0));
            query[r * 2 + 1] = static_cast<float>(static_cast<double>(segment[r * 2 + 1]) + step);
        }
        const auto scan = scan_of(segment, 4, 2, {0});
        const double d2 = kboracle::oracle_squared_distance(query.data(), segment.data(), 8);
        const auto near =
            scan.nearest(scan.prepare(query.data(), 1)[0], segment.data(), std::nextafter(d2, kInf), kInf);
        REQUIRE(near);
        REQUIRE(near->squared_distance == d2);
    }
}

TEST_CASE("prepared queries hold their signatures as defined, across the bit words' edges",
          "[kb][signature]") {
    // channels 0, 2 and 5 of 6 are binary in the KB's segments, whose values all lie in [-1, 1]
    const std::vector<std::size_t> binary{0, 2, 5};
    const std::size_t channels = 6;
    Rng rng(61);
    for (std::size_t width = 1; width <= 50; ++width) {  // 3 to 150 bits: one to three words
        const std::size_t dim = width * channels;
        std::vector<float> segments(3 * dim);
        for (std::size_t k = 0; k < segments.size(); ++k) {
            const bool is_binary = k % channels == 0 || k % channels == 2 || k % channels == 5;
            segments[k] =
                is_binary ? static_cast<float>(rng.below(2)) : static_cast<float>(rng.uniform() * 2 - 1);
        }
        const kb::SignatureScan scan = scan_of(segments, width, channels, binary);
        // three queries: 0/1 binary channels; one 0.5 in a binary channel; magnitudes above the KB's
        std::vector<float> queries(3 * dim);
        std::vector<float> largest(3, 0.0f);
        for (std::size_t k = 0; k < queries.size(); ++k) {
            const std::size_t q = k / dim;
            const bool is_binary = k % channels == 0 || k % channels == 2 || k % channels == 5;
            queries[k] = is_binary
                             ? static_cast<float>(rng.below(2))
                             : static_cast<float>((rng.uniform() * 2 - 1) * static_cast<double>(q + 2) * 10);
            largest[q] = std::max(largest[q], std::fabs(queries[k]));
        }
        queries[dim + (width - 1) * channels + 2] = 0.5f;  // query 1, last row, channel 2
        const auto prepared = scan.prepare(queries.data(), 3);
        for (std::size_t q = 0; q < 3; ++q) {
            const kb::SignatureScan::Query got = prepared[q];
            INFO("width " << width << ", query " << q);
            const float* query = queries.data() + q * dim;
            CHECK(got.values == query);
            std::vector<std::uint64_t> bits((width * binary.size() + 63) / 64, 0);
            std::vector<std::uint64_t> mask(bits.size(), 0);
            bool all_binary = true;
            for (std::size_t j = 0; j < binary.size(); ++j) {
                int ones = 0;
                for (std::size_t r = 0; r < width; ++r) {
                    const float v = query[r * channels + binary[j]];
                    const std::size_t bit = r * binary.size() + j;
                    if (v == 1.0f) bits[bit / 64] |= std::uint64_t{1} << (bit % 64);
                    if (v == 1.0f || v == 0.0f) mask[bit / 64] |= std::uint64_t{1} << (bit % 64);
                    all_binary = all_binary && (v == 1.0f || v == 0.0f);
                    ones += v == 1.0f;
                }
                CHECK(static_cast<int>(got.counts[j]) == ones);
            }
            for (std::size_t w = 0; w < bits.size(); ++w) {
                CHECK(got.bits[w] == bits[w]);
                CHECK(got.mask[w] == mask[w]);
            }
            CHECK(got.counts_usable == all_binary);
            CHECK(all_binary == (q != 1));
            CHECK(got.sums_usable);
        }
        // the pad scales with the largest magnitude, each query's own above the KB's
        CHECK(prepared[1].pad / prepared[0].pad ==
              Approx(static_cast<double>(largest[1]) / largest[0]).epsilon(1e-12));
        CHECK(prepared[2].pad / prepared[0].pad ==
              Approx(static_cast<double>(largest[2]) / largest[0]).epsilon(1e-12));
    }
}
