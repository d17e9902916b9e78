#include <array>
#include <catch2/catch.hpp>
#include <map>
#include <nlohmann/json.hpp>

#include "core/embedded.hpp"
#include "db/database.hpp"
#include "exp/evaluation.hpp"
#include "exp/evolution.hpp"
#include "nn/genome.hpp"
#include "runs/evolve_config.hpp"
#include "sim/task.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;

TEST_CASE("generation_times.sql sums the phases of a real run", "[exp][queries]") {
    test::TempDir dir;
    test::write_file(dir / "c.json", R"({"task": {"steps_per_start": 200, "starts": 1},
                                          "ea": {"population_size": 8, "generations": 3}, "seed": 2})");
    exp::EvolveOptions options;
    options.config_path = dir / "c.json";
    options.db_path = dir / "run.db";
    options.progress = ProgressMode::quiet;
    exp::run_evolve(options);

    std::string_view text;
    for (const auto& file : query_files()) {
        if (file.path == "generation_times.sql") text = file.text;
    }
    REQUIRE(!text.empty());
    auto connection = db::open_database(dir / "run.db", db::OpenMode::read_only);
    auto query = connection.prepare(text);
    REQUIRE(query.step());
    // generations 1 to 3, 8 children each; the phases fit inside the wall time
    CHECK(query.column_int(1) == 3);
    const double phases = query.column_double(3) + query.column_double(4) + query.column_double(5) +
                          query.column_double(6) + query.column_double(7);
    CHECK(phases <= query.column_double(8) * 1.000001);
    CHECK(query.column_double(2) > 0);
    CHECK(!query.step());
}

TEST_CASE("milestones.sql counts what replaying every stored genome on the simulator gives",
          "[exp][queries][milestones]") {
    // a target run keeping every genome; the oracle evaluates each genome again
    // (sim::run_episode through exp::evaluate_genome) and counts by generation
    test::TempDir dir;
    test::write_file(dir / "c.json", R"({"task": {"kind": "target", "steps_per_start": 600, "starts": 2},
                                          "ea": {"population_size": 16, "generations": 4}, "seed": 5,
                                          "retain": "all"})");
    exp::EvolveOptions options;
    options.config_path = dir / "c.json";
    options.db_path = dir / "run.db";
    options.progress = ProgressMode::quiet;
    exp::run_evolve(options);

    auto connection = db::open_database(dir / "run.db", db::OpenMode::read_only);
    const auto config = runs::EvolveConfig::load(dir / "c.json");
    const auto task = sim::make_task(config.task);
    // generation -> {policies, pressed, picked up, carried, released at the basket, collected}
    std::map<std::int64_t, std::array<std::int64_t, 6>> expected;
    auto genomes = connection.prepare(
        "SELECT i.generation, g.genome FROM individual AS i JOIN genome AS g "
        "ON g.run_id = i.run_id AND g.individual_id = i.id ORDER BY i.id");
    std::int64_t replayed = 0;
    while (genomes.step()) {
        const auto genome = nn::Genome::from_json(nlohmann::json::parse(genomes.column_text(1)));
        const auto e = exp::evaluate_genome(*task, genome, config.dnn);
        auto& row = expected[genomes.column_int(0)];
        row[0] += 1;
        row[1] += e.milestones.presses > 0;
        row[2] += e.milestones.pickups > 0;
        row[3] += e.milestones.carry_steps > 0;
        row[4] += e.milestones.basket_releases > 0;
        row[5] += e.balls > 0;
        ++replayed;
    }
    CHECK(replayed == connection.query_int("SELECT count(*) FROM individual").value_or(-1));

    std::string_view text;
    for (const auto& file : query_files()) {
        if (file.path == "milestones.sql") text = file.text;
    }
    REQUIRE(!text.empty());
    auto query = connection.prepare(text);
    std::size_t rows = 0;
    std::int64_t pressed = 0;
    while (query.step()) {
        const auto g = query.column_int(1);
        INFO("generation " << g);
        REQUIRE(expected.count(g) == 1);
        for (int k = 0; k < 6; ++k)
            CHECK(query.column_int(2 + k) == expected[g][static_cast<std::size_t>(k)]);
        pressed += query.column_int(3);
        ++rows;
    }
    CHECK(rows == expected.size());
    CHECK(rows == 5);
    CHECK(pressed > 0);  // random networks press the switch (the pilot: generation 0 in 3 of 3 runs)
}
