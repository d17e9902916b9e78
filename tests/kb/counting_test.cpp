// The counting rules of observe: by occurrence (every matching segment) and by
// policy (the paper's footnote 1: each KB segment once per policy).

#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "core/error.hpp"
#include "core/rng.hpp"
#include "kb/knowledge_base.hpp"
#include "oracle.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;

namespace {

kb::KbParams counting_params(std::size_t width, std::size_t channels, double delta, kb::Counting counting) {
    kb::KbParams p = kboracle::params_of(width, channels, delta);
    p.counting = counting;
    return p;
}

}  // namespace

TEST_CASE("counting by policy credits a KB segment once per policy, by hand", "[kb][observe][counting]") {
    // delta 1 in 2-D. Policy A (reward 1): (0,0) inserted as id 0, (0.1,0)
    // matches it. Policy B (reward 0.5): (0.05,0) and (0.2,0) both match id 0,
    // (5,5) is inserted as id 1.
    //   by occurrence: id 0 gets 1 + 1 + 0.5 + 0.5 = 3 over 4; id 1 0.5 over 1
    //   by policy:     id 0 gets 1 + 0.5 = 1.5 over 2;        id 1 0.5 over 1
    const std::vector<float> a{0, 0, 0.1f, 0};
    const std::vector<float> b{0.05f, 0, 0.2f, 0, 5, 5};
    for (const auto counting : {kb::Counting::occurrence, kb::Counting::policy}) {
        CAPTURE(kb::to_string(counting));
        kb::KnowledgeBase kb(counting_params(1, 2, 1.0, counting));
        const std::uint32_t src = kb.add_source("run");
        const auto ra = kb.observe(kb::Segments{a, 2}, 1.0, {src, 0});
        const auto rb = kb.observe(kb::Segments{b, 2}, 0.5, {src, 1});
        // matched counts every matching segment whatever the rule
        CHECK(ra.matched == 1);
        CHECK(rb.matched == 2);
        CHECK(rb.inserted == 1);
        REQUIRE(kb.size() == 2);
        const bool once = counting == kb::Counting::policy;
        CHECK(kb.record(0).count == (once ? 2u : 4u));
        CHECK(kb.record(0).cum_reward == (once ? 1.5 : 3.0));
        CHECK(kb.record(0).average() == 0.75);
        CHECK(kb.record(1).count == 1);
        CHECK(kb.record(1).cum_reward == 0.5);
        CHECK(kb.sources()[0].policies == 2);
    }
}

TEST_CASE("counting by policy equals the footnote's oracle on random and clustered policies",
          "[kb][observe][counting]") {
    // small KBs go to brute force, large ones to the tree: both paths
    for (const std::size_t n : {40u, 2000u}) {
        CAPTURE(n);
        const std::size_t dim = 30, per_policy = 10;
        const double delta = 0.3 * std::sqrt(static_cast<double>(dim));
        Rng rng(41, n, 0, Purpose::test);
        const std::vector<float> data = kboracle::clustered_segments(rng, n, dim, 6, 0.3);
        kb::KnowledgeBase kb(counting_params(2, 15, delta, kb::Counting::policy));
        kboracle::OracleKb oracle{dim, delta, {}, {}, {}};
        const std::uint32_t src = kb.add_source("run");
        for (std::size_t p = 0; p * per_policy * dim < data.size(); ++p) {
            const std::vector<float> segs(
                data.begin() + static_cast<std::ptrdiff_t>(p * per_policy * dim),
                data.begin() + static_cast<std::ptrdiff_t>((p + 1) * per_policy * dim));
            const double reward = static_cast<double>(rng.below(5)) / 4.0;
            kb.observe(kb::Segments{segs, dim}, reward, {src, static_cast<std::int64_t>(p)});
            oracle.observe_per_policy(segs, reward);
            REQUIRE(kb.size() == oracle.size());
        }
        std::uint64_t repeats = 0;
        for (std::size_t i = 0; i < kb.size(); ++i) {
            REQUIRE(kb.record(i).count == oracle.count[i]);
            REQUIRE(kb.record(i).cum_reward == oracle.cum_reward[i]);
            repeats += kb.record(i).count;
        }
        // the data repeat behaviours within policies, so the rule is exercised:
        // by policy, fewer credits than segments observed
        CHECK(repeats < n);
    }
}

TEST_CASE("KBs of different counting rules do not merge", "[kb][merge][counting][errors]") {
    kb::KnowledgeBase by_policy(counting_params(1, 2, 1.0, kb::Counting::policy));
    kb::KnowledgeBase by_occurrence(counting_params(1, 2, 1.0, kb::Counting::occurrence));
    const std::vector<float> seg{0, 0};
    by_occurrence.observe(kb::Segments{seg, 2}, 1.0, {by_occurrence.add_source("b"), 0});
    REQUIRE_THROWS_AS(by_policy.merge(by_occurrence), DataError);
    REQUIRE_THROWS_WITH(by_policy.merge(by_occurrence),
                        Contains("counts by policy") && Contains("by occurrence"));
    CHECK(by_policy.size() == 0);
    CHECK(by_policy.sources().empty());
    // the same rule merges, and the rule is kept by coarsening and randomizing
    kb::KnowledgeBase other(counting_params(1, 2, 1.0, kb::Counting::policy));
    other.observe(kb::Segments{seg, 2}, 1.0, {other.add_source("c"), 0});
    by_policy.merge(other);
    CHECK(by_policy.size() == 1);
    CHECK(by_policy.coarsened(2.0).params().counting == kb::Counting::policy);
    CHECK(by_policy.randomized(3).params().counting == kb::Counting::policy);
}

TEST_CASE("counting rules are named and parsed with one-line errors", "[kb][counting][errors]") {
    CHECK(kb::parse_counting("policy") == kb::Counting::policy);
    CHECK(kb::parse_counting("occurrence") == kb::Counting::occurrence);
    CHECK(std::string(kb::to_string(kb::Counting::policy)) == "policy");
    REQUIRE_THROWS_AS(kb::parse_counting("policies", "kb.counting"), ConfigError);
    REQUIRE_THROWS_WITH(kb::parse_counting("policies", "kb.counting"),
                        Contains("kb.counting") && Contains("occurrence|policy") && Contains("policies"));
}
