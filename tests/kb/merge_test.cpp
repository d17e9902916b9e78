#include <catch2/catch.hpp>

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

kb::KnowledgeBase from_values(const kb::KbParams& p, const std::string& run, std::vector<float> values,
                              std::vector<kb::SegmentRecord> records) {
    return kb::KnowledgeBase::from_segments(p, {kb::Source{run, 0, 9, 10}}, values, records);
}

// `policies` policies of `per` segments each around well-separated centres
// (spread << delta << gap between centres), each with its reward
struct Observations {
    std::vector<std::vector<float>> policies;
    std::vector<double> rewards;
};

Observations make_observations(Rng& rng, std::size_t dim, const std::vector<float>& centres, std::size_t count) {
    Observations o;
    const std::size_t k = centres.size() / dim;
    for (std::size_t p = 0; p < count; ++p) {
        std::vector<float> segs(5 * dim);
        for (std::size_t s = 0; s < 5; ++s) {
            const std::size_t c = static_cast<std::size_t>(rng.below(k));
            for (std::size_t d = 0; d < dim; ++d)
                segs[s * dim + d] = centres[c * dim + d] + static_cast<float>(rng.uniform(-0.01, 0.01));
        }
        o.policies.push_back(std::move(segs));
        o.rewards.push_back(static_cast<double>(rng.below(9)) / 8.0);
    }
    return o;
}

kb::KnowledgeBase observed(const kb::KbParams& p, const std::string& run, const Observations& o) {
    kb::KnowledgeBase kb(p);
    const std::uint32_t src = kb.add_source(run);
    for (std::size_t i = 0; i < o.policies.size(); ++i)
        kb.observe(kb::Segments{o.policies[i], p.dim()}, o.rewards[i], {src, static_cast<std::int64_t>(i)});
    return kb;
}

}  // namespace

TEST_CASE("merging adds counts and cumulated rewards of matched segments and inserts the others", "[kb][merge]") {
    // by hand, 1-D, delta 1: A = {0: (1, 2)}; B = {0.5: (0.5, 1), 7: (3, 3)}
    const kb::KbParams p = params_of(1, 1, 1.0);
    kb::KnowledgeBase a = from_values(p, "run-a", {0.0f}, {{1.0, 2, {0, 1}, {0, 4}}});
    const kb::KnowledgeBase b = from_values(p, "run-b", {0.5f, 7.0f}, {{0.5, 1, {0, 2}, {0, 3}}, {3.0, 3, {0, 5}, {0, 8}}});
    a.merge(b);
    REQUIRE(a.size() == 2);
    CHECK(a.record(0).cum_reward == 1.5);
    CHECK(a.record(0).count == 3);
    CHECK(a.segment(0)[0] == 0.0f);  // A's values stay
    CHECK(a.record(1).cum_reward == 3.0);
    CHECK(a.record(1).count == 3);
    CHECK(a.segment(1)[0] == 7.0f);
    // provenance: B's source appended; last of the credited segment is B's last
    REQUIRE(a.sources().size() == 2);
    CHECK(a.sources()[1].run == "run-b");
    CHECK(a.sources()[1].policies == 10);
    CHECK(a.record(0).first.source == 0);
    CHECK(a.record(0).last.source == 1);
    CHECK(a.record(0).last.generation == 3);
    CHECK(a.record(1).first.source == 1);
    CHECK(a.record(1).first.generation == 5);
}

TEST_CASE("merging A with B then C equals the paper's rule applied to the same observations", "[kb][merge]") {
    // with behaviours around centres much farther apart than delta and noise
    // much smaller than delta, each KB holds one segment per centre seen, and
    // the merge must give what observing all three runs in order gives
    Rng rng(12, 0, 0, Purpose::test);
    const std::size_t dim = 30;
    std::vector<float> centres = kboracle::uniform_segments(rng, 25, dim);
    for (float& v : centres) v *= 20.0f;
    const kb::KbParams p = params_of(10, 3, 0.5);
    const Observations oa = make_observations(rng, dim, centres, 40);
    const Observations ob = make_observations(rng, dim, centres, 40);
    const Observations oc = make_observations(rng, dim, centres, 40);

    kb::KnowledgeBase merged = observed(p, "a", oa);
    merged.merge(observed(p, "b", ob));
    merged.merge(observed(p, "c", oc));

    kboracle::OracleKb oracle{dim, 0.5, {}, {}, {}};
    for (const Observations* o : {&oa, &ob, &oc})
        for (std::size_t i = 0; i < o->policies.size(); ++i) oracle.observe(o->policies[i], o->rewards[i]);

    REQUIRE(merged.size() == oracle.size());
    CHECK(std::vector<float>(merged.values().begin(), merged.values().end()) == oracle.values);
    for (std::size_t i = 0; i < merged.size(); ++i) {
        CHECK(merged.record(i).count == oracle.count[i]);
        // rewards are multiples of 1/8: sums are exact in any grouping
        CHECK(merged.record(i).cum_reward == oracle.cum_reward[i]);
    }
    REQUIRE(merged.sources().size() == 3);
    CHECK(merged.sources()[2].run == "c");
    CHECK(merged.sources()[2].policies == 40);
}

TEST_CASE("merging in the order given is the paper's rule applied to B's segments with their statistics", "[kb][merge]") {
    // the general case, any data: the oracle observes B's segments one by
    // one into A, carrying (cum_reward, count)
    Rng rng(13, 0, 0, Purpose::test);
    const std::size_t dim = 45;
    const kb::KbParams p = params_of(3, 15, 1.6);
    Observations oa, ob;
    for (int i = 0; i < 30; ++i) {
        oa.policies.push_back(kboracle::clustered_segments(rng, 20, dim, 15, 0.3));
        oa.rewards.push_back(rng.uniform());
        ob.policies.push_back(kboracle::clustered_segments(rng, 20, dim, 15, 0.3));
        ob.rewards.push_back(rng.uniform());
    }
    kb::KnowledgeBase a = observed(p, "a", oa);
    const kb::KnowledgeBase b = observed(p, "b", ob);

    kboracle::OracleKb oracle{dim, 1.6, std::vector<float>(a.values().begin(), a.values().end()), {}, {}};
    for (const auto& r : a.records()) {
        oracle.cum_reward.push_back(r.cum_reward);
        oracle.count.push_back(r.count);
    }
    for (std::size_t i = 0; i < b.size(); ++i) oracle.add(b.segment(i).data(), b.record(i).cum_reward, b.record(i).count);

    a.merge(b);
    REQUIRE(a.size() == oracle.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
        REQUIRE(a.record(i).count == oracle.count[i]);
        REQUIRE(a.record(i).cum_reward == oracle.cum_reward[i]);
    }
}

TEST_CASE("KBs of different width, channels or delta are refused naming both values", "[kb][merge][errors]") {
    kb::KnowledgeBase a = from_values(params_of(2, 1, 1.83), "a", {0, 0}, {{1, 1, {0, 0}, {0, 0}}});
    const kb::KnowledgeBase width = from_values(params_of(1, 2, 1.83), "b", {0, 0}, {{1, 1, {0, 0}, {0, 0}}});
    const kb::KnowledgeBase channels = from_values(params_of(2, 2, 1.83), "b", {0, 0, 0, 0}, {{1, 1, {0, 0}, {0, 0}}});
    const kb::KnowledgeBase delta = from_values(params_of(2, 1, 2.5), "b", {9, 9}, {{1, 1, {0, 0}, {0, 0}}});
    REQUIRE_THROWS_AS(a.merge(width), DataError);
    REQUIRE_THROWS_WITH(a.merge(width), Contains("segment_width is 2") && Contains(", 1 in the merged"));
    REQUIRE_THROWS_WITH(a.merge(channels), Contains("channels is 1") && Contains(", 2 in the merged"));
    REQUIRE_THROWS_WITH(a.merge(delta), Contains("delta is 1.83") && Contains(", 2.5 in the merged"));
    CHECK(a.size() == 1);
    CHECK(a.sources().size() == 1);
    CHECK(a.record(0).count == 1);
}

TEST_CASE("a KB merged with itself doubles its statistics", "[kb][merge]") {
    // every segment is at distance 0 from itself: counts and rewards double
    kb::KnowledgeBase a = from_values(params_of(1, 1, 1.0), "a", {0, 5}, {{1, 2, {0, 0}, {0, 0}}, {0.5, 1, {0, 1}, {0, 1}}});
    a.merge(a);
    REQUIRE(a.size() == 2);
    CHECK(a.record(0).count == 4);
    CHECK(a.record(0).cum_reward == 2.0);
    CHECK(a.record(1).count == 2);
    CHECK(a.sources().size() == 1);
    CHECK(a.sources()[0].policies == 20);
}

TEST_CASE("coarsening re-observes the segments in id order under the larger delta", "[kb][merge][coarsen]") {
    // one channel, width 1, delta 1: 0, 1.5, 3, 10 are more than 1 apart
    const auto p = params_of(1, 1, 1.0);
    const auto kb = from_values(p, "run", {0.0f, 1.5f, 3.0f, 10.0f},
                                {{0.5, 2, {0, 1}, {0, 3}}, {0.25, 1, {0, 2}, {0, 2}},
                                 {1.0, 4, {0, 4}, {0, 6}}, {0.0, 1, {0, 5}, {0, 5}}});
    // delta 2 by hand: 0 inserted; 1.5 is 1.5 < 2 from 0: credited; 3 is 3 from 0 (nearest): inserted; 10 inserted
    const auto coarse = kb.coarsened(2.0);
    CHECK(coarse.params().delta == 2.0);
    REQUIRE(coarse.size() == 3);
    CHECK(coarse.segment(1)[0] == 3.0f);
    CHECK(coarse.record(0).cum_reward == 0.75);
    CHECK(coarse.record(0).count == 3);
    CHECK(coarse.record(0).last.generation == 2);  // the absorbed segment's last origin
    CHECK(coarse.record(1).count == 4);
    REQUIRE(coarse.sources().size() == 1);
    CHECK(coarse.sources()[0].run == "run");
    CHECK(coarse.sources()[0].policies == 10);
    // delta 3.5: 0 takes 1.5 and 3 (3 < 3.5); 10 stays apart
    const auto coarser = kb.coarsened(3.5);
    REQUIRE(coarser.size() == 2);
    CHECK(coarser.record(0).cum_reward == 1.75);
    CHECK(coarser.record(0).count == 7);
    // the same delta keeps every segment; a smaller or non-finite one is refused
    CHECK(kb.coarsened(1.0).size() == 4);
    CHECK_THROWS_AS(kb.coarsened(0.5), ConfigError);
    CHECK_THROWS_WITH(kb.coarsened(0.5), Contains("at least the KB's 1"));
    CHECK_THROWS_AS(kb.coarsened(std::numeric_limits<double>::quiet_NaN()), ConfigError);
}
