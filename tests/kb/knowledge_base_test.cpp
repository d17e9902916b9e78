#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <vector>

#include "core/error.hpp"
#include "core/rng.hpp"
#include "kb/knowledge_base.hpp"
#include "oracle.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;

namespace {

using kboracle::params_of;

// observes `policies` policies of `per_policy` segments into both KBs and
// requires identical contents after every policy
void observe_both(kb::KnowledgeBase& kb, kboracle::OracleKb& oracle, const std::vector<float>& data,
                  std::size_t per_policy, Rng& rewards) {
    const std::size_t dim = oracle.dim;
    const std::size_t policies = data.size() / dim / per_policy;
    const std::uint32_t source = kb.add_source("run");
    for (std::size_t p = 0; p < policies; ++p) {
        std::vector<float> segs(data.begin() + static_cast<std::ptrdiff_t>(p * per_policy * dim),
                                data.begin() + static_cast<std::ptrdiff_t>((p + 1) * per_policy * dim));
        const double reward = static_cast<double>(rewards.below(5)) / 4.0;
        kb.observe(kb::Segments{segs, dim}, reward, kb::Origin{source, static_cast<std::int64_t>(p)});
        oracle.observe(segs, reward);
        REQUIRE(kb.size() == oracle.size());
    }
    REQUIRE(std::vector<float>(kb.values().begin(), kb.values().end()) == oracle.values);
    for (std::size_t i = 0; i < kb.size(); ++i) {
        REQUIRE(kb.record(i).count == oracle.count[i]);
        REQUIRE(kb.record(i).cum_reward == oracle.cum_reward[i]);
    }
}

// lookups of `queries` under both rules against the oracle's linear scan
void check_lookups(const kb::KnowledgeBase& kb, const kboracle::OracleKb& oracle,
                   const std::vector<float>& queries) {
    const std::size_t dim = oracle.dim;
    kb::KbParams nearest_params = kb.params();
    nearest_params.match = kb::Match::nearest;
    std::vector<kb::SegmentRecord> records(kb.records().begin(), kb.records().end());
    std::vector<kb::Source> sources(kb.sources().begin(), kb.sources().end());
    const kb::KnowledgeBase nearest_kb = kb::KnowledgeBase::from_segments(nearest_params, sources, kb.values(), records);

    const kb::Lookup within = kb.lookup(kb::Segments{queries, dim});
    const kb::Lookup nearest = nearest_kb.lookup(kb::Segments{queries, dim});
    double r_within = 0, r_nearest = 0;
    for (std::size_t i = 0; i * dim < queries.size(); ++i) {
        const float* q = queries.data() + i * dim;
        const auto expect_within = oracle.within(q);
        const auto expect_nearest = kboracle::oracle_nearest(oracle.values, dim, q);
        REQUIRE(within.segments[i].id.has_value() == expect_within.has_value());
        if (expect_within) {
            REQUIRE(*within.segments[i].id == expect_within->first);
            REQUIRE(within.segments[i].distance == std::sqrt(expect_within->second));
            REQUIRE(within.segments[i].average_reward ==
                    oracle.cum_reward[expect_within->first] / static_cast<double>(oracle.count[expect_within->first]));
        }
        REQUIRE(nearest.segments[i].id.has_value() == expect_nearest.has_value());
        if (expect_nearest) {
            REQUIRE(*nearest.segments[i].id == expect_nearest->first);
            REQUIRE(nearest.segments[i].distance == std::sqrt(expect_nearest->second));
        }
        const double a = within.segments[i].average_reward, b = nearest.segments[i].average_reward;
        r_within = i == 0 ? a : std::max(r_within, a);
        r_nearest = i == 0 ? b : std::max(r_nearest, b);
    }
    CHECK(within.r_max == r_within);
    CHECK(nearest.r_max == r_nearest);
    CHECK(kb.r_max(kb::Segments{queries, dim}) == r_within);
}

struct Shape {
    std::size_t width, channels;
};

}  // namespace

TEST_CASE("params are validated with one-line messages naming the value", "[kb][errors]") {
    // the message form of docs/development.md: "delta must be > 0, got -1"
    REQUIRE_THROWS_AS(kb::KnowledgeBase(params_of(20, 15, -1)), ConfigError);
    REQUIRE_THROWS_WITH(kb::KnowledgeBase(params_of(20, 15, -1)), Contains("delta must be > 0") && Contains("got -1"));
    REQUIRE_THROWS_WITH(kb::KnowledgeBase(params_of(20, 15, 0)), Contains("got 0"));
    REQUIRE_THROWS_WITH(kb::KnowledgeBase(params_of(20, 15, std::nan(""))), Contains("delta") && Contains("nan"));
    REQUIRE_THROWS_WITH(kb::KnowledgeBase(params_of(20, 15, HUGE_VAL)), Contains("delta") && Contains("inf"));
    REQUIRE_THROWS_WITH(kb::KnowledgeBase(params_of(0, 15, 1)), Contains("segment_width must be >= 1, got 0"));
    REQUIRE_THROWS_WITH(kb::KnowledgeBase(params_of(20, 0, 1)), Contains("channels must be >= 1, got 0"));
    try {
        kb::KnowledgeBase bad(params_of(20, 15, -1));
    } catch (const ConfigError& e) {
        CHECK(std::string(e.what()).find('\n') == std::string::npos);
    }
}

TEST_CASE("observe and lookup equal a linear-scan oracle on random and clustered data", "[kb][observe]") {
    // dims from 2 to 300: (width, channels) = (1,2), (3,1), (5,3), (4,15), (20,15)
    const Shape shapes[] = {{1, 2}, {3, 1}, {5, 3}, {4, 15}, {20, 15}};
    for (const Shape shape : shapes) {
        const std::size_t dim = shape.width * shape.channels;
        // a delta near the typical nearest distance, so both matches and inserts happen
        const double delta = 0.35 * std::sqrt(static_cast<double>(dim));
        for (int kind = 0; kind < 2; ++kind) {
            CAPTURE(dim, kind);
            Rng rng(17 + dim, static_cast<std::uint64_t>(kind), 0, Purpose::test);
            const std::size_t n = dim >= 60 ? 1200 : 2000;
            const std::vector<float> data = kind == 0 ? kboracle::uniform_segments(rng, n, dim)
                                                      : kboracle::clustered_segments(rng, n, dim, 12, 0.3);
            kb::KnowledgeBase kb(params_of(shape.width, shape.channels, delta));
            kboracle::OracleKb oracle{dim, delta, {}, {}, {}};
            observe_both(kb, oracle, data, 20, rng);
            const std::vector<float> queries = kind == 0
                                                   ? kboracle::uniform_segments(rng, 150, dim)
                                                   : kboracle::clustered_segments(rng, 150, dim, 12, 0.4);
            check_lookups(kb, oracle, queries);
        }
    }
}

TEST_CASE("ties and distances exactly at delta follow the documented rule", "[kb][observe][ties]") {
    // values on a grid of 1/4 make many segments equidistant and many
    // distances exactly 0.5 = delta; the oracle applies d2 < delta^2 with
    // ties to the lowest id
    for (std::size_t dim : {2u, 3u, 8u}) {
        CAPTURE(dim);
        Rng rng(5, dim, 0, Purpose::test);
        const std::vector<float> data = kboracle::grid_segments(rng, 600, dim, 4);
        kb::KnowledgeBase kb(params_of(1, dim, 0.5));
        kboracle::OracleKb oracle{dim, 0.5, {}, {}, {}};
        observe_both(kb, oracle, data, 10, rng);
        check_lookups(kb, oracle, kboracle::grid_segments(rng, 200, dim, 5));
    }
}

TEST_CASE("a policy that repeats segments gets every repeat matched as the oracle says", "[kb][observe]") {
    // lookups search each distinct segment once: repeats of a segment, far
    // apart or in a row, and a policy of one segment shown 40 times must
    // still get the oracle's match at every position, on the tree and on
    // brute force (a small KB)
    for (const std::size_t n : {1500u, 12u}) {
        CAPTURE(n);
        const std::size_t dim = 60;
        const double delta = 0.35 * std::sqrt(static_cast<double>(dim));
        Rng rng(23, n, 0, Purpose::test);
        kb::KnowledgeBase kb(params_of(4, 15, delta));
        kboracle::OracleKb oracle{dim, delta, {}, {}, {}};
        observe_both(kb, oracle, kboracle::clustered_segments(rng, n, dim, 12, 0.3), 4, rng);
        const std::vector<float> distinct = kboracle::clustered_segments(rng, 30, dim, 12, 0.4);
        std::vector<float> queries;
        for (const std::size_t i : {0u, 1u, 1u, 2u, 0u, 3u, 29u, 1u, 3u, 3u, 17u, 0u}) {
            queries.insert(queries.end(), distinct.begin() + i * dim, distinct.begin() + (i + 1) * dim);
        }
        check_lookups(kb, oracle, queries);
        std::vector<float> still;
        for (int i = 0; i < 40; ++i)
            still.insert(still.end(), distinct.begin() + 5 * dim, distinct.begin() + 6 * dim);
        check_lookups(kb, oracle, still);
    }
}

TEST_CASE("a segment exactly delta away is inserted and a closer one is credited", "[kb][observe][ties]") {
    // by hand in 2-D with delta 1.5: (1.5, 0) is at distance exactly 1.5 from
    // (0, 0), so not closer than delta; (1.25, 0) is
    kb::KnowledgeBase kb(params_of(1, 2, 1.5));
    const std::uint32_t src = kb.add_source("run");
    const std::vector<float> origin{0, 0}, at_delta{1.5f, 0};
    kb.observe(kb::Segments{origin, 2}, 1.0, {src, 0});
    const kb::ObserveResult r1 = kb.observe(kb::Segments{at_delta, 2}, 0.5, {src, 1});
    CHECK(r1.inserted == 1);
    CHECK(kb.size() == 2);
    // (0.25, 0) is 0.25 from (0,0) and 1.25 from (1.5,0): credited to id 0
    const std::vector<float> near0{0.25f, 0};
    kb.observe(kb::Segments{near0, 2}, 0.5, {src, 2});
    CHECK(kb.record(0).count == 2);
    CHECK(kb.record(0).cum_reward == 1.5);
    // (0.75, 0) is 0.75 from both: the tie goes to the lowest id, 0
    const std::vector<float> middle{0.75f, 0};
    kb.observe(kb::Segments{middle, 2}, 0.25, {src, 3});
    CHECK(kb.record(0).count == 3);
    CHECK(kb.record(1).count == 1);
}

TEST_CASE("a segment inserted earlier in the same policy absorbs later ones", "[kb][observe]") {
    // one policy with segments (0,0), (0.1,0), (5,5), (5,5.1) and delta 1:
    // sequentially, (0.1,0) matches the just-inserted (0,0), likewise for (5,5.1)
    kb::KnowledgeBase kb(params_of(1, 2, 1.0));
    const std::uint32_t src = kb.add_source("run");
    const std::vector<float> policy{0, 0, 0.1f, 0, 5, 5, 5, 5.1f};
    const kb::ObserveResult r = kb.observe(kb::Segments{policy, 2}, 0.75, {src, 4});
    CHECK(r.inserted == 2);
    CHECK(r.matched == 2);
    REQUIRE(kb.size() == 2);
    CHECK(kb.record(0).count == 2);
    CHECK(kb.record(0).cum_reward == 1.5);
    CHECK(kb.record(1).count == 2);
}

TEST_CASE("r_max is the largest average among the matches, unmatched segments counting 0", "[kb][lookup]") {
    // by hand: KB of 1-D segments {0: avg 0.2, 10: avg 0.9 (cum 1.8 / 2), 20: avg -0.5}, delta 1
    const std::vector<float> values{0, 10, 20};
    const std::vector<kb::SegmentRecord> records{{0.2, 1, {0, 0}, {0, 0}}, {1.8, 2, {0, 0}, {0, 1}}, {-0.5, 1, {0, 2}, {0, 2}}};
    const std::vector<kb::Source> sources{{"run", 0, 2, 4}};
    const kb::KnowledgeBase kb = kb::KnowledgeBase::from_segments(params_of(1, 1, 1.0), sources, values, records);

    // 0.5 -> id 0 (0.2); 9.5 -> id 1 (0.9); 5 -> none: r_max 0.9
    const std::vector<float> q1{0.5f, 9.5f, 5.0f};
    const kb::Lookup l1 = kb.lookup(kb::Segments{q1, 1});
    CHECK(*l1.segments[0].id == 0);
    CHECK(*l1.segments[1].id == 1);
    CHECK_FALSE(l1.segments[2].id.has_value());
    CHECK(l1.segments[1].distance == 0.5);
    CHECK(l1.segments[1].average_reward == 0.9);
    CHECK(l1.r_max == 0.9);
    // 20.2 -> -0.5, 5 -> no match (0): r_max 0
    const std::vector<float> q2{20.2f, 5.0f};
    CHECK(kb.r_max(kb::Segments{q2, 1}) == 0.0);
    // only 20.2: r_max is its average, -0.5
    const std::vector<float> q3{20.2f};
    CHECK(kb.r_max(kb::Segments{q3, 1}) == -0.5);
    // match = nearest: 5 goes to id 0 (distance 5, tie with 10 broken by the lowest id)
    kb::KbParams p = kb.params();
    p.match = kb::Match::nearest;
    const kb::KnowledgeBase nearest = kb::KnowledgeBase::from_segments(p, sources, values, records);
    const kb::Lookup l2 = nearest.lookup(kb::Segments{q2, 1});
    CHECK(*l2.segments[1].id == 0);
    CHECK(l2.segments[1].distance == 5.0);
    CHECK(l2.r_max == 0.2);
    // an empty KB gives 0
    const kb::KnowledgeBase empty(params_of(1, 1, 1.0));
    CHECK(empty.r_max(kb::Segments{q1, 1}) == 0.0);
    CHECK(empty.max_average() == 0.0);
    CHECK(kb.max_average() == 0.9);
}

TEST_CASE("bad segments and rewards are refused and leave the KB unchanged", "[kb][errors]") {
    kb::KnowledgeBase kb(params_of(2, 2, 1.0));
    const std::uint32_t src = kb.add_source("run");
    const std::vector<float> good{0, 0, 0, 0, 3, 3, 3, 3};
    kb.observe(kb::Segments{good, 4}, 1.0, {src, 0});
    REQUIRE(kb.size() == 2);
    const std::vector<float> before(kb.values().begin(), kb.values().end());

    // NaN in the second segment: the first (a match) must not be credited either
    std::vector<float> nan_values{0, 0, 0, 0, 9, std::nanf(""), 9, 9};
    REQUIRE_THROWS_AS(kb.observe(kb::Segments{nan_values, 4}, 1.0, {src, 1}), DataError);
    REQUIRE_THROWS_WITH(kb.observe(kb::Segments{nan_values, 4}, 1.0, {src, 1}),
                        Contains("segment 1") && Contains("non-finite"));
    std::vector<float> inf_values{HUGE_VALF, 0, 0, 0};
    REQUIRE_THROWS_AS(kb.observe(kb::Segments{inf_values, 4}, 1.0, {src, 1}), DataError);
    // wrong dimension, ragged length, non-finite reward, unknown source
    REQUIRE_THROWS_WITH(kb.observe(kb::Segments{good, 2}, 1.0, {src, 1}), Contains("2 values") && Contains("uses 4"));
    const std::vector<float> ragged{0, 0, 0, 0, 1};
    REQUIRE_THROWS_WITH(kb.observe(kb::Segments{ragged, 4}, 1.0, {src, 1}), Contains("not a whole number"));
    REQUIRE_THROWS_WITH(kb.observe(kb::Segments{good, 4}, std::nan(""), {src, 1}), Contains("reward must be finite"));
    REQUIRE_THROWS_WITH(kb.observe(kb::Segments{good, 4}, 1.0, {7, 1}), Contains("source 7"));
    REQUIRE_THROWS_AS(kb.lookup(kb::Segments{nan_values, 4}), DataError);
    REQUIRE_THROWS_AS(kb.nearest(std::span<const float>(good).first(3)), DataError);

    CHECK(kb.size() == 2);
    CHECK(std::vector<float>(kb.values().begin(), kb.values().end()) == before);
    CHECK(kb.record(0).count == 1);
    CHECK(kb.record(0).cum_reward == 1.0);
    CHECK(kb.sources()[0].policies == 1);
}

TEST_CASE("a lookup names the first segment with a NaN or infinity on every search path", "[kb][errors]") {
    // the tree path leaves the check to the index (which computes each
    // query's largest magnitude anyway); the brute-force path, the small
    // index and the nearest rule check the values first: all must give the
    // same message, for the first bad segment and its first bad position
    Rng rng(31, 0, 0, Purpose::test);
    const std::size_t dim = 60;
    const std::vector<float> data = kboracle::clustered_segments(rng, 1500, dim, 20, 0.3);
    std::vector<kb::SegmentRecord> records(1500, kb::SegmentRecord{1.0, 1, {}, {}});
    const std::vector<kb::Source> sources{kb::Source{"run", 0, 0, 1}};
    const kb::KnowledgeBase tree = kb::KnowledgeBase::from_segments(params_of(4, 15, 2.0), sources, data, records);
    REQUIRE_FALSE(tree.index().brute_force());
    // values so large that float bounds could overflow send the index to brute force
    std::vector<float> large = data;
    for (float& v : large) v *= 1e16f;
    const kb::KnowledgeBase brute = kb::KnowledgeBase::from_segments(params_of(4, 15, 2.0), sources, large, records);
    REQUIRE(brute.index().brute_force());
    const std::vector<float> few(data.begin(), data.begin() + 10 * dim);
    const kb::KnowledgeBase small = kb::KnowledgeBase::from_segments(
        params_of(4, 15, 2.0), sources, few, std::span<const kb::SegmentRecord>(records).first(10));
    const kb::KnowledgeBase nearest =
        kb::KnowledgeBase::from_segments(params_of(4, 15, 2.0, kb::Match::nearest), sources, data, records);

    std::vector<float> queries = kboracle::clustered_segments(rng, 200, dim, 20, 0.4);
    REQUIRE_NOTHROW(tree.lookup(kb::Segments{queries, dim}));
    queries[57 * dim + 13] = std::nanf("");
    queries[57 * dim + 40] = HUGE_VALF;
    queries[120 * dim + 2] = -HUGE_VALF;
    for (const kb::KnowledgeBase* kb : {&tree, &brute, &small, &nearest}) {
        REQUIRE_THROWS_AS(kb->lookup(kb::Segments{queries, dim}), DataError);
        REQUIRE_THROWS_WITH(kb->lookup(kb::Segments{queries, dim}), "segment 57 has a non-finite value at position 13");
        REQUIRE_THROWS_WITH(kb->r_max(kb::Segments{queries, dim}), "segment 57 has a non-finite value at position 13");
    }
    // an infinity alone, late in the policy, on the tree path
    queries[57 * dim + 13] = 0.0f;
    queries[57 * dim + 40] = 0.0f;
    REQUIRE_THROWS_WITH(tree.lookup(kb::Segments{queries, dim}), "segment 120 has a non-finite value at position 2");
}

TEST_CASE("provenance records the first and last observation of each segment and the sources", "[kb][provenance]") {
    kb::KnowledgeBase kb(params_of(1, 1, 1.0));
    const std::uint32_t a = kb.add_source("run-a");
    const std::uint32_t b = kb.add_source("run-b");
    CHECK(kb.add_source("run-a") == a);
    const std::vector<float> s0{0}, s5{5};
    kb.observe(kb::Segments{s0, 1}, 1, {a, 10});
    kb.observe(kb::Segments{s5, 1}, 1, {a, 20});
    kb.observe(kb::Segments{s0, 1}, 1, {b, 3});
    CHECK(kb.record(0).first.source == a);
    CHECK(kb.record(0).first.generation == 10);
    CHECK(kb.record(0).last.source == b);
    CHECK(kb.record(0).last.generation == 3);
    CHECK(kb.record(1).first.generation == 20);
    CHECK(kb.record(1).last.generation == 20);
    REQUIRE(kb.sources().size() == 2);
    CHECK(kb.sources()[a].run == "run-a");
    CHECK(kb.sources()[a].first_generation == 10);
    CHECK(kb.sources()[a].last_generation == 20);
    CHECK(kb.sources()[a].policies == 2);
    CHECK(kb.sources()[b].policies == 1);
    REQUIRE_THROWS_WITH(kb.add_source(""), Contains("run name"));
}

TEST_CASE("a KB rebuilt from its arrays answers every lookup identically", "[kb][load]") {
    Rng rng(99, 0, 0, Purpose::test);
    const std::size_t dim = 60;
    const std::vector<float> data = kboracle::clustered_segments(rng, 1500, dim, 20, 0.3);
    kb::KnowledgeBase kb(params_of(4, 15, 2.0));
    const std::uint32_t src = kb.add_source("run");
    for (std::size_t p = 0; p < 75; ++p)
        kb.observe(kb::Segments{std::span<const float>(data).subspan(p * 20 * dim, 20 * dim), dim}, 0.1 * double(p % 7), {src, std::int64_t(p)});

    std::vector<kb::SegmentRecord> records(kb.records().begin(), kb.records().end());
    std::vector<kb::Source> sources(kb.sources().begin(), kb.sources().end());
    const kb::KnowledgeBase loaded = kb::KnowledgeBase::from_segments(kb.params(), sources, kb.values(), records);
    const kb::KnowledgeBase copied = kb;
    const std::vector<float> queries = kboracle::clustered_segments(rng, 300, dim, 20, 0.4);
    const kb::Lookup a = kb.lookup(kb::Segments{queries, dim});
    for (const kb::KnowledgeBase* other : {&loaded, &copied}) {
        const kb::Lookup b = other->lookup(kb::Segments{queries, dim});
        CHECK(a.r_max == b.r_max);
        for (std::size_t i = 0; i < a.segments.size(); ++i) {
            REQUIRE(a.segments[i].id == b.segments[i].id);
            REQUIRE(a.segments[i].distance == b.segments[i].distance);
        }
    }
    // bad arrays are refused
    records[3].count = 0;
    REQUIRE_THROWS_WITH(kb::KnowledgeBase::from_segments(kb.params(), sources, kb.values(), records),
                        Contains("segment 3 has count 0"));
    records[3].count = 1;
    REQUIRE_THROWS_WITH(kb::KnowledgeBase::from_segments(kb.params(), sources, kb.values().first(10), records),
                        Contains("10 values"));
    records[2].last.source = 4;
    REQUIRE_THROWS_WITH(kb::KnowledgeBase::from_segments(kb.params(), sources, kb.values(), records),
                        Contains("source 4"));
}
