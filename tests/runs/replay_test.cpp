// Replays of stored genomes (lib/runs/replay.cpp) against the rewards the
// engine stored when it evaluated them, on a tiny run made by stepstone evolve.
#include "runs/replay.hpp"

#include <catch2/catch.hpp>

#include "core/error.hpp"
#include "db/database.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;

TEST_CASE("every stored genome replays to its stored reward, and an individual that is no id is refused",
          "[runs][replay]") {
    test::TempDir dir;
    test::write_file(dir / "c.json", R"({
  "task": {"kind": "source", "steps_per_start": 300, "starts": 1},
  "ea": {"population_size": 8, "generations": 3},
  "dnn": {"add_connection_rate": 0.5, "add_neuron_rate": 0.3},
  "seed": 11
})");
    const auto run = dir / "run.db";
    const auto made =
        test::run_cli({"evolve", "--config", (dir / "c.json").string(), "--db", run.string(), "--quiet"});
    INFO(made.err);
    REQUIRE(made.exit_code == 0);
    auto connection = db::open_database(run, db::OpenMode::read_only);
    // replay of every stored genome gives the stored reward exactly
    auto ids = connection.prepare("SELECT individual_id FROM genome ORDER BY individual_id");
    int replayed = 0;
    while (ids.step()) {
        const auto r = runs::replay(run, std::to_string(ids.column_int(0)));
        CHECK(r.result.reward == r.stored_reward);
        ++replayed;
    }
    CHECK(replayed > 0);
    CHECK_THROWS_WITH(runs::replay(run, "abc"),
                      Contains("individual must be 'best' or an individual id") && !Contains("--"));
}
