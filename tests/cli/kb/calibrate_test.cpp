#include "kb/calibrate.hpp"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "db/database.hpp"
#include "runs/replay.hpp"
#include "sim/sensors.hpp"
#include "support/kb_fixtures.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;

TEST_CASE("kb calibrate on a run uses the replayed best policy and the run's stored policies",
          "[cli][kb][calibrate]") {
    test::TempDir dir;
    kbtest::make_run(dir / "run.db");
    const auto run = dir / "run.db";
    auto result = test::run_cli(
        {"kb", "calibrate", run.string(), "--individual", "best", "--deltas", "0.25,1,4", "--json"});
    REQUIRE(result.exit_code == 0);
    const auto out = nlohmann::json::parse(result.out);

    // oracle: the library's rule on the replayed behaviour, width from the run's KB (10, not the default 20)
    runs::Replay best;
    const auto behaviour = runs::replay_behaviour(run, "best", &best);
    const auto channels = static_cast<std::size_t>(sim::kChannels);
    CHECK(out["segment_width"] == kbtest::kRunWidth);
    CHECK(out["segment_width_from"] == "the run's knowledge base");
    CHECK(out["individual_id"] == best.individual_id);
    CHECK(out["segments"] == kbtest::kRunSteps / kbtest::kRunWidth);
    CHECK(out["delta"].get<double>() ==
          kb::calibrate_delta(kb::segment_behaviour(behaviour, channels, kbtest::kRunWidth), 20));

    // the size table over every stored genome, in id order
    std::vector<std::vector<float>> behaviours;
    {
        auto connection = db::open_database(run, db::OpenMode::read_only);
        auto select = connection.prepare("SELECT individual_id FROM genome ORDER BY individual_id");
        while (select.step())
            behaviours.push_back(runs::replay_behaviour(run, std::to_string(select.column_int(0))));
    }
    std::vector<kb::Segments> segments;
    for (const auto& b : behaviours)
        segments.push_back(kb::segment_behaviour(b, channels, kbtest::kRunWidth));
    kb::KbParams params;
    params.segment_width = kbtest::kRunWidth;
    params.channels = channels;
    const std::vector<double> deltas{0.25, 1, 4};
    const auto sizes = kb::kb_sizes(params, segments, deltas);
    CHECK(out["policies"] == behaviours.size());
    REQUIRE(out["sizes"].size() == 3);
    for (std::size_t i = 0; i < 3; ++i) {
        CHECK(out["sizes"][i]["delta"] == deltas[i]);
        CHECK(out["sizes"][i]["segments"] == sizes[i].size);
    }
    // a larger delta never gives a larger KB
    CHECK(sizes[0].size >= sizes[1].size);
    CHECK(sizes[1].size >= sizes[2].size);

    // --segment-width overrides the run's KB; the text form names the rule
    result = test::run_cli({"kb", "calibrate", run.string(), "--segment-width", "20"});
    REQUIRE(result.exit_code == 0);
    CHECK_THAT(result.out, Contains("segment_width   20 (--segment-width)"));
    CHECK_THAT(result.out, Contains("segments        10 of 15 channels"));
    CHECK_THAT(result.out, Contains("KB size over the"));
}

TEST_CASE("kb calibrate --deltas none gives the delta alone", "[cli][kb][calibrate]") {
    test::TempDir dir;
    kbtest::make_run(dir / "run.db");
    const auto run = dir / "run.db";
    const auto full = test::run_cli({"kb", "calibrate", run.string(), "--json", "--quiet"});
    const auto alone = test::run_cli({"kb", "calibrate", run.string(), "--deltas", "none", "--json"});
    REQUIRE(full.exit_code == 0);
    REQUIRE(alone.exit_code == 0);
    const auto a = nlohmann::json::parse(full.out);
    const auto b = nlohmann::json::parse(alone.out);
    CHECK(b["delta"] == a["delta"]);
    CHECK(b["sizes"].empty());
    CHECK(a["sizes"].size() == 8);
    CHECK(b["policies"] == 0);
}

TEST_CASE("kb calibrate --reading windows gives both window variants beside the segments reading",
          "[cli][kb][calibrate][windows]") {
    test::TempDir dir;
    kbtest::make_run(dir / "run.db");
    const auto run = dir / "run.db";
    const auto result = test::run_cli(
        {"kb", "calibrate", run.string(), "--reading", "windows", "--deltas", "none", "--json"});
    REQUIRE(result.exit_code == 0);
    const auto out = nlohmann::json::parse(result.out);
    const auto behaviour = runs::replay_behaviour(run, "best");
    const auto channels = static_cast<std::size_t>(sim::kChannels);
    const auto expected = kb::calibrate_delta_windows(behaviour, channels, kbtest::kRunWidth);
    CHECK(out["reading"] == "windows");
    CHECK(out["windows"]["windows"] == kbtest::kRunSteps - kbtest::kRunWidth + 1);
    CHECK(out["windows"]["delta_excluding_overlap"].get<double>() == expected.excluding_overlap);
    CHECK(out["windows"]["delta_including_overlap"].get<double>() == expected.including_overlap);
    CHECK(out["delta"].get<double>() ==
          kb::calibrate_delta(kb::segment_behaviour(behaviour, channels, kbtest::kRunWidth), 20));
    // the default reading prints no window figures; the text names both variants
    const auto plain = test::run_cli({"kb", "calibrate", run.string(), "--deltas", "none", "--json"});
    CHECK(nlohmann::json::parse(plain.out)["reading"] == "segments");
    CHECK_FALSE(nlohmann::json::parse(plain.out).contains("windows"));
    const auto text =
        test::run_cli({"kb", "calibrate", run.string(), "--reading", "windows", "--deltas", "none"});
    CHECK_THAT(text.out, Contains("share no step with it") && Contains("overlapping windows included"));
    const auto bad = test::run_cli({"kb", "calibrate", run.string(), "--reading", "strides"});
    CHECK(bad.exit_code != 0);
    CHECK_THAT(bad.err, Contains("--reading"));
}
