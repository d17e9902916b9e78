#include "runs/events_campaign.hpp"

#include <catch2/catch.hpp>
#include <map>
#include <string>

#include "db/database.hpp"
#include "support/run_cli.hpp"

namespace stepstone::runstest {

namespace {

// the shipped KB fixture, then none and sum x 3 seeds x 4 generations, population 8
std::string campaign_json() {
    return std::string(R"({
  "kb": {"file": ")") +
           STEPSTONE_SOURCE_DIR + R"(/examples/fixtures/demo_kb.db.gz"},
  "randomize_seed": 1,
  "target": {
    "config": {"task": {"kind": "target", "steps_per_start": 200, "starts": 1}, "ea": {"population_size": 8}},
    "runs": 3, "generations": 4, "treatments": ["none", "sum"]
  }
})";
}

// the first generation of each milestone set by hand: every individual's
// milestones cleared, then one individual of generation g given the milestone
void set_first(const std::filesystem::path& run, const std::map<std::string, int>& first) {
    auto connection = db::open_database(run, db::OpenMode::read_write);
    connection.exec(
        "UPDATE individual SET presses = 0, pickups = 0, carry_steps = 0, basket_releases = 0, balls = 0");
    const std::map<std::string, std::string> column = {
        {"press", "presses"}, {"pickup", "pickups"}, {"release", "basket_releases"}, {"ball", "balls"}};
    for (const auto& [event, generation] : first) {
        connection.exec("UPDATE individual SET " + column.at(event) +
                        " = 2 WHERE id = (SELECT min(id) FROM " +
                        "individual WHERE generation = " + std::to_string(generation) + ")");
    }
}

}  // namespace

EventsCampaign::EventsCampaign() {
    test::write_file(dir / "c.json", campaign_json());
    const auto made =
        test::run_cli({"campaign", (dir / "c.json").string(), "--dir", camp.string(), "--quiet"});
    INFO(made.err);
    REQUIRE(made.exit_code == 0);
    // pickups: none at 3, never, never; sum at 0, 1, 4. Presses at 0 everywhere; no release, one ball
    for (int seed = 1; seed <= 3; ++seed) {
        std::map<std::string, int> none{{"press", 0}}, sum{{"press", 0}};
        if (seed == 1) none["pickup"] = 3;
        sum["pickup"] = seed == 1 ? 0 : seed == 2 ? 1 : 4;
        if (seed == 3) sum["ball"] = 4;
        set_first(camp / "target" / "none" / ("seed-" + std::to_string(seed) + ".db"), none);
        set_first(camp / "target" / "sum" / ("seed-" + std::to_string(seed) + ".db"), sum);
    }
}

}  // namespace stepstone::runstest
