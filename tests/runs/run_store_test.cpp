// The run store (lib/runs/run_store.cpp) on a run written by hand: the run
// row's counters as generations are written, the stored genomes and the best
// of them (highest reward, lowest id on ties), the checkpoint, and a genome
// that was not stored.
#include "runs/run_store.hpp"

#include <catch2/catch.hpp>

#include "core/error.hpp"
#include "db/database.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;

namespace {

runs::IndividualRow individual(std::int64_t id, int generation, double reward) {
    runs::IndividualRow row;
    row.id = id;
    row.generation = generation;
    row.reward = reward;
    row.fitness = reward;
    return row;
}

runs::GenomeRow genome(std::int64_t id) { return {id, nlohmann::json{{"genome_of", id}}.dump()}; }

}  // namespace

TEST_CASE(
    "a run's counters add up its generations, and its best stored genome is the highest reward, lowest id",
    "[runs][store]") {
    test::TempDir dir;
    auto connection = db::open_database(dir / "run.db", db::OpenMode::create);
    runs::RunRecord run;
    run.task = "source";
    run.seed = 3;
    run.config = nlohmann::json{{"seed", 3}};
    run.generations = 1;
    run.id = runs::insert_run(connection, run, "test");
    const auto fresh = runs::load_run(connection);
    CHECK(fresh.status == runs::RunStatus::running);
    CHECK(fresh.generations_done == -1);
    CHECK(fresh.config == run.config);
    CHECK_FALSE(runs::load_checkpoint(connection, run.id));

    // generation 0: four policies (rewards 0.5, 0.75, 0.75, 0.25), genomes of 1, 2 and 3 kept
    runs::GenerationWrite first;
    first.stats.generation = 0;
    first.stats.evaluations = 4;
    first.nan_outputs = 1;
    first.individuals = {individual(0, 0, 0.5), individual(1, 0, 0.75), individual(2, 0, 0.75),
                         individual(3, 0, 0.25)};
    first.genomes = {genome(1), genome(2), genome(3)};
    first.checkpoint = {{"at", 0}};
    runs::write_generation(connection, run, first);
    // generation 1: two children (0.125 and 0.75), the second kept
    runs::GenerationWrite second;
    second.stats.generation = 1;
    second.stats.evaluations = 2;
    second.nan_outputs = 2;
    second.individuals = {individual(4, 1, 0.125), individual(5, 1, 0.75)};
    second.genomes = {genome(5)};
    second.checkpoint = {{"at", 1}};
    runs::write_generation(connection, run, second);

    const auto loaded = runs::load_run(connection);
    CHECK(loaded.generations_done == 1);
    CHECK(loaded.evaluations == 4 + 2);
    CHECK(loaded.nan_outputs == 1 + 2);
    CHECK(loaded.evaluations == run.evaluations);  // the caller's record follows the file
    CHECK(runs::load_checkpoint(connection, run.id) == nlohmann::json{{"at", 1}});

    CHECK(runs::stored_individuals(connection, run.id) == std::vector<std::int64_t>{1, 2, 3, 5});
    // 0.75 three times (ids 1, 2 and 5): the lowest id
    const auto best = runs::load_best_genome(connection, run.id);
    CHECK(best.individual_id == 1);
    CHECK(best.reward == 0.75);
    CHECK(best.generation == 0);
    CHECK(best.genome == nlohmann::json{{"genome_of", 1}});
    CHECK(runs::load_genome(connection, run.id, 5).generation == 1);
    CHECK_THROWS_AS(runs::load_genome(connection, run.id, 0), DataError);
    CHECK_THROWS_WITH(runs::load_genome(connection, run.id, 4),
                      Contains("individual 4 has no stored genome"));

    run.status = runs::RunStatus::finished;
    runs::update_run(connection, run);
    CHECK(runs::load_run(connection).status == runs::RunStatus::finished);
}
