// The brute-force KB of the `kb` cases keeps the KB's observe rule: the nearest segment
// within delta is credited, else the segment is inserted, and a policy's later segments
// see the ones it inserted.

#include "reference/brute_kb.hpp"

#include <catch2/catch.hpp>
#include <vector>

#include "kb/knowledge_base.hpp"

using namespace stepstone;

TEST_CASE("the brute-force KB credits the nearest segment within delta and inserts the others",
          "[bench][kb]") {
    kb::KbParams params;
    params.segment_width = 1;
    params.channels = 2;
    params.delta = 1.0;
    const std::vector<float> values{0, 0, 5, 5};
    const std::vector<kb::SegmentRecord> records(2, kb::SegmentRecord{0.5, 1, {0, 0}, {0, 0}});
    reference::BruteKb brute(
        kb::KnowledgeBase::from_segments(params, {kb::Source{"hand", 0, 0, 1}}, values, records));
    REQUIRE(brute.size() == 2);
    REQUIRE(brute.dim() == 2);

    // (0.5, 0): 0.5 from (0, 0), credited. (3, 3): sqrt(8) from (5, 5), inserted as segment 2.
    // (3.5, 3): 0.5 from the segment this policy just inserted, credited to it.
    const std::vector<float> policy{0.5f, 0, 3, 3, 3.5f, 3};
    brute.observe_batched(policy.data(), 3, 1.0);
    REQUIRE(brute.size() == 3);
    CHECK(brute.count(0) == 2);
    CHECK(brute.cum_reward(0) == 1.5);
    CHECK(brute.count(1) == 1);
    CHECK(brute.cum_reward(1) == 0.5);
    CHECK(brute.count(2) == 2);
    CHECK(brute.cum_reward(2) == 2.0);

    // exactly delta away is not within delta: (1, 0) from (0, 0) is inserted
    const std::vector<float> edge{1, 0};
    brute.observe_batched(edge.data(), 1, 0.25);
    CHECK(brute.size() == 4);

    brute.reset();
    CHECK(brute.size() == 2);
    CHECK(brute.count(0) == 1);
    CHECK(brute.cum_reward(0) == 0.5);
}
