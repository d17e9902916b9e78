// What a KB refuses so that its sums stay finite and its names printable:
// rewards beyond kMaxRewardMagnitude, records that no valid rewards could
// sum to, and run names that are empty, too long, not UTF-8 or hold control
// characters.

#include <catch2/catch.hpp>
#include <cfloat>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "kb/knowledge_base.hpp"
#include "oracle.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;

TEST_CASE("a reward beyond the bound is refused before anything changes, and sums at the bound stay finite",
          "[kb][errors][bounds]") {
    // 9.2e18 (the largest count a database holds) x the bound is below DBL_MAX: no sum can overflow
    CHECK(9.3e18 * kb::kMaxRewardMagnitude < DBL_MAX);
    kb::KnowledgeBase kb(kboracle::params_of(2, 2, 1.0));
    const std::uint32_t src = kb.add_source("run");
    const std::vector<float> twice{0, 0, 0, 0, 0, 0, 0, 0};  // one segment, repeated: one record, count 2
    kb.observe(kb::Segments{twice, 4}, kb::kMaxRewardMagnitude, {src, 0});
    kb.observe(kb::Segments{twice, 4}, kb::kMaxRewardMagnitude, {src, 1});
    REQUIRE(kb.size() == 1);
    CHECK(kb.record(0).count == 4);
    CHECK(kb.record(0).cum_reward == 4 * kb::kMaxRewardMagnitude);
    // the service's 1e308 twice on one segment would have made Inf
    CHECK_THROWS_WITH(kb.observe(kb::Segments{twice, 4}, 1e308, {src, 2}),
                      Contains("reward 1e+308 is beyond +-1e+289"));
    CHECK_THROWS_AS(kb.observe(kb::Segments{twice, 4}, -1e290, {src, 2}), DataError);
    CHECK(kb.record(0).count == 4);
    CHECK(kb.sources()[0].policies == 2);
}

TEST_CASE("a loaded record whose cum_reward no valid rewards reach is refused, naming it",
          "[kb][errors][bounds]") {
    const auto params = kboracle::params_of(2, 2, 1.0);
    const std::vector<float> values{0, 0, 0, 0, 5, 5, 5, 5};
    std::vector<kb::SegmentRecord> records{{1.0, 1, {0, 0}, {0, 0}}, {3e289, 2, {0, 0}, {0, 0}}};
    const std::vector<kb::Source> sources{{"run", 0, 0, 1}};
    CHECK_THROWS_WITH(kb::KnowledgeBase::from_segments(params, sources, values, records),
                      Contains("segment 1 has cum_reward 3e+289 over 2 policies"));
    records[1].cum_reward = -2e289;  // exactly count x the bound: accepted
    CHECK(kb::KnowledgeBase::from_segments(params, sources, values, records).size() == 2);
}

TEST_CASE("run names: 1 to 256 bytes of UTF-8 without control characters", "[kb][errors][names]") {
    for (const std::string& good :
         std::vector<std::string>{"run", "seed-1", "r\xc3\xa9sum\xc3\xa9", "\xe6\x97\xa5\xe6\x9c\xac",
                                  "\xf0\x9f\x99\x82", std::string(256, 'a')}) {
        INFO(good);
        CHECK_NOTHROW(kb::check_run_name(good, "name"));
    }
    const std::pair<std::string, const char*> bad[] = {
        {"", "name is empty"},
        {std::string(257, 'a'), "257 bytes, more than 256"},
        {std::string("a\0b", 3), "control character (byte 1)"},
        {"tab\there", "control character (byte 3)"},
        {"x\xff", "not valid UTF-8 (byte 1)"},
        {"\xc0\xaf", "not valid UTF-8 (byte 0)"},          // overlong '/'
        {"\xe0\x80\xaf", "not valid UTF-8 (byte 0)"},      // overlong, three bytes
        {"\xed\xa0\x80", "not valid UTF-8 (byte 0)"},      // a surrogate
        {"\xf4\x90\x80\x80", "not valid UTF-8 (byte 0)"},  // beyond U+10FFFF
        {"ab\xe6\x97", "not valid UTF-8 (byte 2)"},        // cut short
        {"\x80", "not valid UTF-8 (byte 0)"},              // a lone continuation byte
    };
    for (const auto& [name, message] : bad) {
        INFO(message);
        CHECK_THROWS_WITH(kb::check_run_name(name, "name"), Contains(message));
    }
    // the KB applies it to every source it registers or loads
    kb::KnowledgeBase kb(kboracle::params_of(2, 2, 1.0));
    CHECK_THROWS_WITH(kb.add_source(std::string("a\0b", 3)), Contains("control character"));
    CHECK(kb.sources().empty());
    const std::vector<kb::Source> sources{{std::string(300, 'r'), 0, 0, 0}};
    CHECK_THROWS_WITH(kb::KnowledgeBase::from_segments(kboracle::params_of(2, 2, 1.0), sources, {}, {}),
                      Contains("source 0's run name has 300 bytes"));
}
