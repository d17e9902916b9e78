#include "kb/salient_index.hpp"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdint>
#include <vector>

#include "core/rng.hpp"
#include "kb/knowledge_base.hpp"
#include "oracle.hpp"

using namespace stepstone;

namespace {

using kboracle::params_of;

// r_max by linear scan, straight from the definition: each query's nearest KB
// segment (lowest id on ties), within delta unless `nearest`, gives its
// average, an unmatched query 0; the largest of them (0 for no queries)
double oracle_r_max(const std::vector<float>& values, const std::vector<kb::SegmentRecord>& records,
                    std::size_t dim, double delta, bool nearest, const std::vector<float>& queries) {
    double r_max = 0.0;
    for (std::size_t i = 0; i * dim < queries.size(); ++i) {
        const auto best = kboracle::oracle_nearest(values, dim, queries.data() + i * dim);
        double reward = 0.0;
        if (best && (nearest || best->second < delta * delta)) reward = records[best->first].average();
        r_max = i == 0 ? reward : std::max(r_max, reward);
    }
    return r_max;
}

// records whose averages are 0 for all but `positive_share` of the segments,
// the others drawn from a few levels (ties between segments) or uniformly
std::vector<kb::SegmentRecord> zero_heavy_records(Rng& rng, std::size_t n, double positive_share) {
    std::vector<kb::SegmentRecord> records(n);
    for (auto& r : records) {
        r.count = 1 + rng.below(3);
        if (rng.uniform() < positive_share) {
            r.cum_reward = rng.uniform() < 0.5
                               ? static_cast<double>(1 + rng.below(4)) / 24.0 * static_cast<double>(r.count)
                               : rng.uniform() * static_cast<double>(r.count);
        }
    }
    return records;
}

// every policy of `policies` (segments of `per_policy` queries near the KB's
// segments or anywhere) gets the oracle's r_max from r_max() and lookup()
void require_oracle(const kb::KnowledgeBase& kb, const std::vector<float>& values,
                    const std::vector<kb::SegmentRecord>& records, Rng& rng, std::size_t policies,
                    std::size_t per_policy, double spread) {
    const std::size_t dim = kb.params().dim();
    for (std::size_t p = 0; p < policies; ++p) {
        std::vector<float> queries(per_policy * dim);
        for (std::size_t i = 0; i < per_policy; ++i) {
            const std::size_t near = rng.below(records.size());
            for (std::size_t d = 0; d < dim; ++d)
                queries[i * dim + d] =
                    values[near * dim + d] + static_cast<float>(rng.uniform(-spread, spread));
        }
        const double expected = oracle_r_max(values, records, dim, kb.params().delta,
                                             kb.params().match == kb::Match::nearest, queries);
        const kb::Segments segments{queries, dim};
        REQUIRE(kb.r_max(segments) == expected);
        REQUIRE(kb.lookup(segments).r_max == expected);
    }
}

}  // namespace

TEST_CASE("r_max through the positive segments equals a linear scan on zero-heavy KBs",
          "[kb][lookup][salient]") {
    const std::size_t dim = 12;
    const std::vector<kb::Source> sources{{"run", 0, 9, 100}};
    for (const std::uint64_t seed : {1u, 2u, 3u}) {
        Rng rng(seed, 0, 0, Purpose::test);
        const auto values = kboracle::clustered_segments(rng, 3000, dim, 40, 0.2);
        const auto records = zero_heavy_records(rng, 3000, 0.15);
        // a small delta (few candidates: one band) and a large one (bands)
        for (const double delta : {0.3, 0.9}) {
            for (const kb::Match match : {kb::Match::within_delta, kb::Match::nearest}) {
                const auto kb =
                    kb::KnowledgeBase::from_segments(params_of(3, 4, delta, match), sources, values, records);
                require_oracle(kb, values, records, rng, 30, 40, 0.25);
            }
        }
    }
}

TEST_CASE("r_max through signature scans equals a linear scan on KBs with binary channels",
          "[kb][lookup][salient]") {
    // the paper's shape: 20 rows x 6 channels, three of them 0/1; queries are
    // KB segments with a few bits flipped and the floats moved
    const std::size_t width = 20, channels = 6, dim = width * channels;
    const std::vector<std::size_t> binary{0, 3, 4};
    const std::vector<kb::Source> sources{{"run", 0, 9, 100}};
    for (const std::uint64_t seed : {1u, 2u}) {
        Rng rng(seed, 0, 0, Purpose::test);
        const auto values = kboracle::binary_segments(rng, 2500, width, channels, binary, 60, 0.02, 0.04);
        const auto records = zero_heavy_records(rng, 2500, 0.2);
        for (const double delta : {1.0, 1.83, 3.84}) {
            for (const kb::Match match : {kb::Match::within_delta, kb::Match::nearest}) {
                const auto kb = kb::KnowledgeBase::from_segments(params_of(width, channels, delta, match),
                                                                 sources, values, records);
                const auto salient = kb::SalientIndex::build(width, channels, delta, values, records);
                REQUIRE(salient);
                REQUIRE(salient->scans());
                REQUIRE(salient->bands() == 2);  // ~500 positive: 256 + the rest
                for (std::size_t p = 0; p < 12; ++p) {
                    std::vector<float> queries(40 * dim);
                    for (std::size_t i = 0; i < 40; ++i) {
                        const std::size_t near = rng.below(records.size());
                        for (std::size_t d = 0; d < dim; ++d) {
                            const float x = values[near * dim + d];
                            const bool is_binary =
                                d % channels == 0 || d % channels == 3 || d % channels == 4;
                            queries[i * dim + d] = is_binary ? (rng.uniform() < 0.01 ? 1.0f - x : x)
                                                             : x + static_cast<float>(rng.uniform(-0.1, 0.1));
                        }
                    }
                    const double expected =
                        oracle_r_max(values, records, dim, delta, match == kb::Match::nearest, queries);
                    const kb::Segments segments{queries, dim};
                    REQUIRE(salient->r_max(
                                queries.data(), 40,
                                match == kb::Match::nearest ? std::nullopt : std::optional<double>(delta),
                                kb::SegmentIndex(width, channels), values, records) == expected);
                    REQUIRE(kb.r_max(segments) == expected);
                }
            }
        }
    }
}

TEST_CASE("signature scans serve KBs of at most 4,096 positive segments, trees the larger ones",
          "[kb][salient]") {
    const std::size_t width = 20, channels = 6;
    Rng rng(4, 0, 0, Purpose::test);
    const auto values = kboracle::binary_segments(rng, 9000, width, channels, {0, 3, 4}, 60, 0.02, 0.04);
    std::vector<kb::SegmentRecord> records(9000, kb::SegmentRecord{0.0, 1, {0, 0}, {0, 0}});
    for (std::size_t i = 0; i < 4096; ++i) records[i].cum_reward = 0.5;
    CHECK(kb::SalientIndex::build(width, channels, 1.83, values, records)->scans());
    records[4096].cum_reward = 0.5;
    const auto large = kb::SalientIndex::build(width, channels, 1.83, values, records);
    CHECK_FALSE(large->scans());
    CHECK(large->size() == 4097);
}

TEST_CASE("the positive segments are cut into bands only when searches check many of them", "[kb][salient]") {
    const std::size_t dim = 12;
    Rng rng(7, 0, 0, Purpose::test);
    const auto values = kboracle::clustered_segments(rng, 4000, dim, 20, 0.2);
    const auto records = zero_heavy_records(rng, 4000, 0.3);
    const auto tight = kb::SalientIndex::build(3, 4, 0.05, values, records);
    const auto wide = kb::SalientIndex::build(3, 4, 2.0, values, records);
    REQUIRE(tight);
    REQUIRE(wide);
    const auto positive = static_cast<std::size_t>(std::count_if(
        records.begin(), records.end(), [](const kb::SegmentRecord& r) { return r.average() > 0; }));
    CHECK(tight->size() == positive);
    CHECK(wide->size() == positive);
    CHECK(tight->bands() == 1);
    CHECK(wide->bands() > 1);

    // a KB with more positive segments than zero ones, or a negative average,
    // is left to the full lookup
    auto mostly_positive = records;
    for (auto& r : mostly_positive) r.cum_reward = 0.5;
    CHECK_FALSE(kb::SalientIndex::build(3, 4, 2.0, values, mostly_positive));
    auto negative = records;
    negative[17].cum_reward = -0.25;
    CHECK_FALSE(kb::SalientIndex::build(3, 4, 2.0, values, negative));
    negative[17].cum_reward = -0.0;  // a signed zero would make r_max -0.0
    CHECK_FALSE(kb::SalientIndex::build(3, 4, 2.0, values, negative));
}

TEST_CASE("a positive segment within delta gives way to a nearer one averaging 0", "[kb][lookup][salient]") {
    // by hand, 1-D: 0 at x = 0 (average 0), 1 at x = 1 (average 0.9), 2 to 9
    // far away (average 0), delta 2. A query at 0.4 is 0.6 from the positive
    // segment but 0.4 from segment 0: its match averages 0, r_max 0. At 0.6
    // the positive segment is the nearer: r_max 0.9
    std::vector<float> values{0, 1};
    std::vector<kb::SegmentRecord> records{{0.0, 1, {0, 0}, {0, 0}}, {0.9, 1, {0, 0}, {0, 0}}};
    for (int k = 2; k < 10; ++k) {
        values.push_back(static_cast<float>(100 * k));
        records.push_back({0.0, 1, {0, 0}, {0, 0}});
    }
    const std::vector<kb::Source> sources{{"run", 0, 0, 10}};
    const auto kb = kb::KnowledgeBase::from_segments(params_of(1, 1, 2.0), sources, values, records);
    const std::vector<float> behind{0.4f, 500.0f};
    const std::vector<float> ahead{0.6f, 500.0f};
    CHECK(kb.r_max(kb::Segments{behind, 1}) == 0.0);
    CHECK(kb.r_max(kb::Segments{ahead, 1}) == 0.9);
    // a tie (0.5 from both) goes to the lowest id, segment 0
    const std::vector<float> tie{0.5f};
    CHECK(kb.r_max(kb::Segments{tie, 1}) == 0.0);
    const std::vector<float> none;
    CHECK(kb.r_max(kb::Segments{none, 1}) == 0.0);
}

TEST_CASE("r_max follows the KB when observe, merge or randomize change its averages",
          "[kb][lookup][salient]") {
    // 1-D KB: ten segments averaging 0 at 0, 10, ..., 90 and one at 5
    // averaging 0.5; delta 1
    std::vector<float> values;
    std::vector<kb::SegmentRecord> records;
    for (int k = 0; k < 10; ++k) {
        values.push_back(static_cast<float>(10 * k));
        records.push_back({0.0, 1, {0, 0}, {0, 0}});
    }
    values.push_back(5.0f);
    records.push_back({0.5, 1, {0, 0}, {0, 0}});
    const std::vector<kb::Source> sources{{"run", 0, 0, 11}};
    auto kb = kb::KnowledgeBase::from_segments(params_of(1, 1, 1.0), sources, values, records);
    const std::vector<float> policy{30.2f, 5.1f};
    REQUIRE(kb.r_max(kb::Segments{policy, 1}) == 0.5);  // builds the positive index

    // a policy rewarded 0.9 at 30.1: segment 3 now averages (0 + 0.9) / 2
    const std::vector<float> rewarded{30.1f};
    kb.observe(kb::Segments{rewarded, 1}, 0.9, {0, 1});
    CHECK(kb.r_max(kb::Segments{policy, 1}) == 0.5);
    const std::vector<float> at_30{30.2f};
    CHECK(kb.r_max(kb::Segments{at_30, 1}) == 0.45);
    // rewarded again: (0.9 + 0.9) / 3 = 0.6 beats segment 10's 0.5
    kb.observe(kb::Segments{rewarded, 1}, 0.9, {0, 2});
    CHECK(kb.r_max(kb::Segments{policy, 1}) == 0.6);

    // merging a KB whose segment at 5 brings 2.5 over 1 count: (0.5 + 2.5) / 2
    const std::vector<float> other_values{5.0f};
    const std::vector<kb::SegmentRecord> other_records{{2.5, 1, {0, 0}, {0, 0}}};
    const auto other =
        kb::KnowledgeBase::from_segments(params_of(1, 1, 1.0), sources, other_values, other_records);
    kb.merge(other);
    CHECK(kb.r_max(kb::Segments{policy, 1}) == 1.5);

    // the randomized copy answers with its own averages (U[0, 1) draws)
    const auto random = kb.randomized(3);
    const std::vector<float> at_0{0.2f};
    CHECK(random.r_max(kb::Segments{at_0, 1}) == random.record(0).average());
    CHECK(random.r_max(kb::Segments{at_0, 1}) > 0.0);
    CHECK(kb.r_max(kb::Segments{at_0, 1}) == 0.0);
}

TEST_CASE("a band's search goes on while r_max stays below the band's lowest average",
          "[kb][lookup][salient]") {
    // by hand, 1-D, delta 10. Positive segments: ids 0-255 at x = id with
    // average 1 - id / 1000 (the top band of 256), ids 256-299 below them
    // (0.744 down to 0.701): id 299 at x = 257.5, id 256 at x = 5000, the others
    // at 6000 + id. 400 segments averaging 0 far away.
    std::vector<float> values;
    std::vector<kb::SegmentRecord> records;
    for (int id = 0; id < 300; ++id) {
        float x = static_cast<float>(id);
        if (id == 299)
            x = 257.5f;
        else if (id == 256)
            x = 5000.0f;
        else if (id > 256)
            x = static_cast<float>(6000 + id);
        values.push_back(x);
        records.push_back({1.0 - id / 1000.0, 1, {0, 0}, {0, 0}});
    }
    for (int j = 0; j < 400; ++j) {
        values.push_back(static_cast<float>(-10000 - j));
        records.push_back({0.0, 1, {0, 0}, {0, 0}});
    }
    const auto salient = kb::SalientIndex::build(1, 1, 10.0, values, records);
    REQUIRE(salient);
    REQUIRE(salient->bands() == 2);
    // 257.3 lies 2.3 from id 255 (top band) but 0.2 from id 299: it gives 0.701,
    // below the top band's lowest (0.745); 5000.2 is within delta of id 256
    // only, which the second band holds: r_max 0.744
    const std::vector<kb::Source> sources{{"run", 0, 0, 700}};
    const auto kb = kb::KnowledgeBase::from_segments(params_of(1, 1, 10.0), sources, values, records);
    const std::vector<float> policy{257.3f, 5000.2f};
    CHECK(kb.r_max(kb::Segments{policy, 1}) == 1.0 - 256 / 1000.0);
    CHECK(kb.lookup(kb::Segments{policy, 1}).r_max == 1.0 - 256 / 1000.0);
    const std::vector<float> first{257.3f};
    CHECK(kb.r_max(kb::Segments{first, 1}) == 1.0 - 299 / 1000.0);
}
