// stepstone export's CSV (lib/runs/export.cpp) of a tiny run file written by
// hand through the run store: its header and rows against the values written.
#include "runs/export.hpp"

#include <catch2/catch.hpp>
#include <sstream>

#include "core/error.hpp"
#include "db/database.hpp"
#include "runs/run_store.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;

namespace {

// a target run of treatment sum, seed 7: one generation of three individuals
void write_tiny_run(const std::filesystem::path& path) {
    auto connection = db::open_database(path, db::OpenMode::create);
    runs::RunRecord run;
    run.task = "target";
    run.treatment = "sum";
    run.seed = 7;
    run.config = nlohmann::json::object();
    run.generations = 1;
    run.id = runs::insert_run(connection, run, "test");

    runs::GenerationWrite write;
    write.stats.generation = 0;
    write.stats.best_reward = 0.5;
    write.stats.mean_reward = 0.25;
    write.stats.median_reward = 0.125;
    write.stats.front_sizes = {2, 1};
    write.stats.diversity_min = 1.5;
    write.stats.diversity_max = 3;
    write.stats.evaluations = 3;
    write.checkpoint = nlohmann::json::object();
    // id, generation, parent, reward, fitness, diversity, r_max, balls, steps, milestones
    runs::IndividualRow a{0, 0, std::nullopt, 0.5, 0.75, 2.5, 0.25, 1, 400, {3, 1, 20, 1}};
    runs::IndividualRow b{1, 0, std::nullopt, 0.125, 0.125, 1.5, std::nullopt, 0, 120, {0, 0, 0, 0}};
    runs::IndividualRow c{2, 0, 0, 0.25, 0.5, 3, 0.5, 0, 400, {1, 0, 0, 0}};
    write.individuals = {a, b, c};
    runs::write_generation(connection, run, write);
}

std::vector<std::string> lines_of(const std::string& text) {
    std::vector<std::string> lines;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
}

}  // namespace

TEST_CASE("export of a tiny run file: the header and a row per individual or generation as written",
          "[runs][export]") {
    test::TempDir dir;
    write_tiny_run(dir / "run.db");

    std::ostringstream individuals;
    CHECK(runs::export_csv(dir / "run.db", runs::ExportWhat::individuals, individuals) == 3);
    const auto rows = lines_of(individuals.str());
    REQUIRE(rows.size() == 4);
    CHECK(rows[0] ==
          "task,treatment,seed,id,generation,parent_id,reward,fitness,diversity,r_max,balls,steps,presses,"
          "pickups,carry_steps,basket_releases");
    // an absent parent or r_max is an empty field
    CHECK(rows[1] == "target,sum,7,0,0,,0.5,0.75,2.5,0.25,1,400,3,1,20,1");
    CHECK(rows[2] == "target,sum,7,1,0,,0.125,0.125,1.5,,0,120,0,0,0,0");
    CHECK(rows[3] == "target,sum,7,2,0,0,0.25,0.5,3,0.5,0,400,1,0,0,0");

    std::ostringstream generations;
    CHECK(runs::export_csv(dir / "run.db", runs::ExportWhat::generations, generations) == 1);
    const auto gens = lines_of(generations.str());
    REQUIRE(gens.size() == 2);
    CHECK(gens[0] ==
          "task,treatment,seed,generation,best_reward,mean_reward,median_reward,first_front_size,fronts,"
          "diversity_min,diversity_max,evaluations,wall_time,time_simulation,time_kb,time_diversity,"
          "time_selection,time_database");
    // the timings that follow are the run store's own (it adds the time the write took)
    CHECK(gens[1].rfind("target,sum,7,0,0.5,0.25,0.125,2,2,1.5,3,3,", 0) == 0);

    CHECK(runs::parse_export_what("kb", "--what") == runs::ExportWhat::kb);
    CHECK_THROWS_WITH(runs::parse_export_what("genomes", "--what"),
                      "--what must be generations, individuals or kb, got \"genomes\"");
    // a file that is not there is named
    std::ostringstream none;
    CHECK_THROWS_WITH(runs::export_csv(dir / "missing.db", runs::ExportWhat::individuals, none),
                      Contains("missing.db"));
}
