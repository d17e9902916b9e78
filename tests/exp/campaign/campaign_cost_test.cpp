// A campaign's cost (lib/exp/campaign/campaign_cost.cpp): evaluations and
// robot steps counted by hand, and the plan --dry-run prints.
#include "exp/campaign/campaign_cost.hpp"

#include <catch2/catch.hpp>
#include <iterator>

#include "support/campaigns.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;

TEST_CASE("campaign --dry-run prints the plan and its cost without touching the disk",
          "[exp][campaign][cli]") {
    test::TempDir dir;
    test::write_file(dir / "c.json", test::tiny_campaign_json(2));
    const auto result = test::run_cli({"campaign", (dir / "c.json").string(), "--dry-run"});
    REQUIRE(result.exit_code == 0);
    // 1 source run: (2 + 3) x 8 = 40 evaluations; 10 target runs: (2 + 2) x 8 = 32 each
    CHECK_THAT(result.out, Contains("11 runs, 360 evaluations"));
    // 40 x 200 + 320 x 200 steps (one start each)
    CHECK_THAT(result.out, Contains("at most 7.2e+04 robot steps"));
    // nothing but the config in the directory
    CHECK(std::distance(std::filesystem::directory_iterator(dir.path()),
                        std::filesystem::directory_iterator()) == 1);
}
