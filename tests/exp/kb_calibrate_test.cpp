// The work behind kb calibrate (lib/exp/kb_calibrate.cpp): the delta rule and
// the KB size table on a hand-made behaviour worked by hand, and on a run the
// size table against the KB's own kb_sizes over the replayed policies, for any
// threads and batch size. The command itself: tests/cli/kb/calibrate_test.cpp.
#include "exp/kb_calibrate.hpp"

#include <catch2/catch.hpp>

#include "core/error.hpp"
#include "db/database.hpp"
#include "kb/calibrate.hpp"
#include "kb/segments.hpp"
#include "runs/replay.hpp"
#include "sim/sensors.hpp"
#include "support/kb_fixtures.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;

TEST_CASE("calibration of a hand-made behaviour follows the mean distance to the nearest others",
          "[exp][kb][calibrate]") {
    // one channel, width 1: segments 0, 1, 3
    const std::vector<float> behaviour{0, 1, 3};
    const std::vector<std::vector<float>> policies{{0, 1, 3}, {0.2f, 10, 10}};
    const std::vector<double> deltas{0.5, 1.5, 10};
    const auto c = exp::calibrate_behaviours(behaviour, policies, 1, 1, deltas);
    // 20 neighbours, 3 segments: each uses its 2 others:
    // 0 -> (1 + 3) / 2 = 2, 1 -> (1 + 2) / 2 = 1.5, 3 -> (3 + 2) / 2 = 2.5; mean 2
    CHECK(c.segments == 3);
    CHECK(c.delta == Approx(2.0));
    CHECK(c.policies == 2);
    // sizes by hand, observing 0, 1, 3, then 0.2, 10, 10:
    // delta 0.5: 0 1 3 inserted, 0.2 within 0.5 of 0, 10 inserted, second 10 credited: 4
    // delta 1.5: 0, (1 credited to 0), 3, (0.2 credited), 10, (10 credited): 3
    // delta 10: 0, (1), (3), (0.2), 10 is at exactly 10 from 0 (not < 10): inserted, (10): 2
    REQUIRE(c.sizes.size() == 3);
    CHECK(c.sizes[0].size == 4);
    CHECK(c.sizes[1].size == 3);
    CHECK(c.sizes[2].size == 2);
    CHECK(c.sizes[2].delta == 10);

    // one neighbour: 0 -> 1, 1 -> 1, 3 -> 2; mean 4/3
    CHECK(exp::calibrate_behaviours(behaviour, {}, 1, 1, {}, 1).delta == Approx(4.0 / 3.0));

    // a 2 x 2 behaviour with width 2 is one segment: the rule needs two
    CHECK_THROWS_AS(exp::calibrate_behaviours(std::vector<float>{0, 1, 2, 3}, {}, 2, 2, {}), DataError);
    CHECK_THROWS_WITH(exp::parse_deltas("1,,2", "--deltas"), Contains("--deltas"));
    CHECK_THROWS_AS(exp::parse_deltas("1,-2", "--deltas"), ConfigError);
    CHECK(exp::parse_deltas("0.5,1.83", "--deltas") == std::vector<double>{0.5, 1.83});
}

TEST_CASE("a run's calibration size table does not depend on threads or batch size", "[exp][kb][calibrate]") {
    test::TempDir dir;
    kbtest::make_run(dir / "run.db");
    const auto run = dir / "run.db";
    exp::CalibrateOptions options;
    options.deltas = {0.25, 1, 4};

    // oracle: one replay per stored genome (all starts), observed in id order by kb_sizes
    std::vector<kb::Segments> segments;
    std::vector<std::vector<float>> behaviours;
    {
        auto connection = db::open_database(run, db::OpenMode::read_only);
        auto select = connection.prepare("SELECT individual_id FROM genome ORDER BY individual_id");
        while (select.step())
            behaviours.push_back(runs::replay_behaviour(run, std::to_string(select.column_int(0))));
    }
    REQUIRE(behaviours.size() >= 4);  // so that a batch of 3 splits them
    for (const auto& b : behaviours)
        segments.push_back(
            kb::segment_behaviour(b, static_cast<std::size_t>(sim::kChannels), kbtest::kRunWidth));
    kb::KbParams params;
    params.segment_width = kbtest::kRunWidth;
    const auto expected = kb::kb_sizes(params, segments, options.deltas);

    for (const auto& [threads, batch] :
         {std::pair{1u, std::size_t{1}}, std::pair{2u, std::size_t{3}}, std::pair{4u, std::size_t{256}}}) {
        options.threads = threads;
        options.batch = batch;
        const auto result = exp::calibrate_run(run, options);
        CHECK(result.calibration.policies == behaviours.size());
        REQUIRE(result.calibration.sizes.size() == expected.size());
        for (std::size_t i = 0; i < expected.size(); ++i) {
            CHECK(result.calibration.sizes[i].delta == expected[i].delta);
            CHECK(result.calibration.sizes[i].size == expected[i].size);
        }
    }
    options.batch = 0;
    CHECK_THROWS_AS(exp::calibrate_run(run, options), ConfigError);
}
