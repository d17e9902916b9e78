#include <catch2/catch.hpp>

#include <vector>

#include "core/rng.hpp"
#include "kb/knowledge_base.hpp"
#include "oracle.hpp"

using namespace stepstone;

namespace {

kb::KnowledgeBase sample_kb() {
    Rng rng(21, 0, 0, Purpose::test);
    kb::KbParams p;
    p.segment_width = 4;
    p.channels = 3;
    p.delta = 0.8;
    kb::KnowledgeBase kb(p);
    const std::uint32_t src = kb.add_source("run");
    for (int i = 0; i < 20; ++i) {
        const std::vector<float> segs = kboracle::clustered_segments(rng, 10, 12, 30, 0.2);
        kb.observe(kb::Segments{segs, 12}, 3.0 * rng.uniform(), {src, i});
    }
    return kb;
}

}  // namespace

TEST_CASE("a randomized KB keeps the segments and draws averages in the unit interval from its seed", "[kb][randomize]") {
    const kb::KnowledgeBase kb = sample_kb();
    REQUIRE(kb.size() > 20);
    const kb::KnowledgeBase r1 = kb.randomized(7);
    const kb::KnowledgeBase r1_again = kb.randomized(7);
    const kb::KnowledgeBase r2 = kb.randomized(8);

    // same segments and provenance
    REQUIRE(r1.size() == kb.size());
    CHECK(std::vector<float>(r1.values().begin(), r1.values().end()) ==
          std::vector<float>(kb.values().begin(), kb.values().end()));
    CHECK(r1.sources().size() == kb.sources().size());
    // the documented draws: i-th uniform of Rng(seed, 0, 0, kb_randomize), count 1
    Rng expect(7, 0, 0, Purpose::kb_randomize);
    std::size_t differs = 0;
    for (std::size_t i = 0; i < kb.size(); ++i) {
        const double u = expect.uniform();
        CHECK(r1.record(i).average() == u);
        CHECK(r1.record(i).average() >= 0.0);
        CHECK(r1.record(i).average() < 1.0);
        CHECK(r1.record(i).count == 1);
        CHECK(r1.record(i).first.generation == kb.record(i).first.generation);
        CHECK(r1_again.record(i).cum_reward == r1.record(i).cum_reward);
        if (r2.record(i).cum_reward != r1.record(i).cum_reward) ++differs;
    }
    CHECK(differs == kb.size());
    // the original is untouched: every record equals that of the same KB built again, never randomized
    const kb::KnowledgeBase fresh = sample_kb();
    REQUIRE(fresh.size() == kb.size());
    for (std::size_t i = 0; i < kb.size(); ++i) {
        CHECK(kb.record(i).cum_reward == fresh.record(i).cum_reward);
        CHECK(kb.record(i).count == fresh.record(i).count);
    }
}
