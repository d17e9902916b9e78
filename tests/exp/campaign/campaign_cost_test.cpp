// A campaign's cost (lib/exp/campaign/campaign_cost.cpp): evaluations and
// robot steps counted by hand, and the plan --dry-run prints.
#include "exp/campaign/campaign_cost.hpp"

#include <catch2/catch.hpp>
#include <iterator>
#include <nlohmann/json.hpp>

#include "runs/campaign_config.hpp"
#include "support/campaigns.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;

TEST_CASE("a tiny campaign's evaluations and robot steps are counted as by hand", "[exp][campaign][cost]") {
    // source: 2 seeds x (3 x 8 initial + 5 x 8) evaluations of 2 starts x 100 steps;
    // target: 3 seeds x 2 treatments x (2 x 12 initial + 4 x 12) evaluations of 3 starts x 50 steps
    const auto config = runs::CampaignConfig::from_json(nlohmann::json::parse(R"({
      "source": {"config": {"task": {"kind": "source", "steps_per_start": 100, "starts": 2},
                            "ea": {"population_size": 8, "initial_multiplier": 3},
                            "kb": {"segment_width": 20}},
                 "seeds": [1, 2], "generations": 5},
      "target": {"config": {"task": {"kind": "target", "steps_per_start": 50, "starts": 3},
                            "ea": {"population_size": 12}},
                 "runs": 3, "generations": 4, "treatments": ["none", "sum"]}
    })"),
                                                        "c.json", std::filesystem::current_path());
    const std::int64_t source = 2 * (3 * 8 + 5 * 8);    // 128
    const std::int64_t target = 6 * (2 * 12 + 4 * 12);  // 432
    const auto cost = exp::estimate_cost(config, 0.01);
    CHECK(cost.runs == 2 + 6);
    CHECK(cost.evaluations == source + target);
    CHECK(cost.robot_steps == static_cast<double>(source * 2 * 100 + target * 3 * 50));  // 90,400
    CHECK(cost.steps_per_second > 0);
    CHECK(cost.cpu_seconds == Approx(cost.robot_steps / cost.steps_per_second));
}

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
