#include "exp/evolution.hpp"

#include <catch2/catch.hpp>

#include "core/error.hpp"
#include "db/database.hpp"
#include "db/digest.hpp"
#include "support/db_files.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;

namespace {

// a tiny run: 8 individuals, one short start; fast enough for many runs per test
const char* kTinyConfig = R"({
  "task": {"kind": "source", "steps_per_start": 300, "starts": 1},
  "ea": {"population_size": 8, "generations": 6},
  "dnn": {"add_connection_rate": 0.5, "add_neuron_rate": 0.3},
  "seed": 11
})";

std::filesystem::path write_config(const test::TempDir& dir, const std::string& text, const char* name = "c.json") {
    test::write_file(dir / name, text);
    return dir / name;
}

exp::EvolveOptions options_for(const test::TempDir& dir, const std::string& db, unsigned threads) {
    exp::EvolveOptions options;
    options.config_path = dir / "c.json";
    options.db_path = dir / db;
    options.threads = threads;
    options.progress = ProgressMode::quiet;
    return options;
}

}  // namespace

TEST_CASE("a run is identical with 1, 2 and 4 threads", "[exp][determinism]") {
    test::TempDir dir;
    write_config(dir, kTinyConfig);
    std::vector<std::string> digests;
    for (unsigned threads : {1u, 2u, 4u}) {
        const std::string name = "t" + std::to_string(threads) + ".db";
        exp::run_evolve(options_for(dir, name, threads));
        digests.push_back(test::file_digest(dir / name));
    }
    CHECK(digests[0] == digests[1]);
    CHECK(digests[0] == digests[2]);
}

TEST_CASE("running 3 generations then resuming to 6 equals running 6", "[exp][determinism][resume]") {
    test::TempDir dir;
    write_config(dir, kTinyConfig);
    exp::run_evolve(options_for(dir, "full.db", 2));

    auto first = options_for(dir, "split.db", 1);
    first.generations = 3;
    exp::run_evolve(first);
    auto second = options_for(dir, "split.db", 2);
    second.resume = true;
    second.generations = 6;
    const auto summary = exp::run_evolve(second);
    CHECK(summary.generations_done == 6);
    CHECK(test::file_digest(dir / "split.db") == test::file_digest(dir / "full.db"));

    // resuming a finished run does nothing and changes nothing
    const auto before = test::file_digest(dir / "full.db");
    auto again = options_for(dir, "full.db", 1);
    again.resume = true;
    CHECK(exp::run_evolve(again).was_finished);
    CHECK(test::file_digest(dir / "full.db") == before);
}

TEST_CASE("the run file holds every generation and individual", "[exp][evolve]") {
    test::TempDir dir;
    write_config(dir, kTinyConfig);
    exp::run_evolve(options_for(dir, "run.db", 2));
    auto connection = db::open_database(dir / "run.db", db::OpenMode::read_only);
    // generations 0..6; 16 random individuals then 8 children per epoch
    CHECK(connection.query_int("SELECT count(*) FROM generation") == 7);
    CHECK(connection.query_int("SELECT count(*) FROM individual") == 16 + 6 * 8);
    CHECK(connection.query_int("SELECT sum(evaluations) FROM generation") == 16 + 6 * 8);
    CHECK(connection.query_int("SELECT count(*) FROM individual WHERE generation > 0 AND parent_id IS NULL") == 0);
    CHECK(connection.query_int("SELECT status = 'finished' AND generations_done = 6 FROM run") == 1);
    // (mu + lambda) elitism: the best reward never decreases
    CHECK(connection.query_int("SELECT count(*) FROM generation AS a JOIN generation AS b "
                               "ON b.generation = a.generation + 1 WHERE b.best_reward < a.best_reward") == 0);
    // every child's parent is an earlier individual
    CHECK(connection.query_int(
              "SELECT count(*) FROM individual AS c JOIN individual AS p ON p.id = c.parent_id "
              "WHERE p.generation >= c.generation") == 0);
}

TEST_CASE("a bad config is refused before any file is written", "[exp][errors]") {
    test::TempDir dir;
    // the messages are EvolveConfig's (tests/runs/evolve_config_test.cpp)
    for (const char* text : {R"({"ea": {"populaton_size": 8}})", R"({"kb": {"period": 0}})"}) {
        INFO(text);
        write_config(dir, text);
        CHECK_THROWS_AS(exp::run_evolve(options_for(dir, "bad.db", 1)), ConfigError);
        CHECK(!std::filesystem::exists(dir / "bad.db"));
    }
}

TEST_CASE("resuming with another config is refused and leaves the run unchanged", "[exp][errors][resume]") {
    test::TempDir dir;
    write_config(dir, kTinyConfig);
    auto options = options_for(dir, "run.db", 1);
    options.generations = 2;
    exp::run_evolve(options);
    const std::string before = test::read_file(dir / "run.db");

    std::string changed = kTinyConfig;
    changed.replace(changed.find("\"population_size\": 8"), 20, "\"population_size\": 12");
    write_config(dir, changed);
    auto resume = options_for(dir, "run.db", 1);
    resume.resume = true;
    CHECK_THROWS_WITH(exp::run_evolve(resume), Contains("run.db: the config differs from the run's at ea.population_size"));
    CHECK(test::read_file(dir / "run.db") == before);

    // an existing file is not replaced without force; the message points to resume first, naming
    // the library's options (the CLI spells them as its flags)
    auto again = options_for(dir, "run.db", 1);
    CHECK_THROWS_WITH(
        exp::run_evolve(again),
        Contains("run.db: already exists; continue it with `resume` (or replace it with `force`)"));
}

namespace {

// the tiny run with a knowledge base observed every 2 generations
const char* kTinyKbConfig = R"({
  "task": {"kind": "source", "steps_per_start": 300, "starts": 1},
  "ea": {"population_size": 8, "generations": 6},
  "dnn": {"add_connection_rate": 0.5, "add_neuron_rate": 0.3},
  "kb": {"segment_width": 20, "delta": 1.0, "period": 2},
  "seed": 11
})";

}  // namespace

TEST_CASE("the run's knowledge base counts every observed segment once", "[exp][kb]") {
    test::TempDir dir;
    write_config(dir, kTinyKbConfig);
    exp::run_evolve(options_for(dir, "run.db", 2));
    auto connection = db::open_database(dir / "run.db", db::OpenMode::read_only);
    // observed generations 0, 2, 4, 6: 16 random policies then 8 children each time;
    // 300 steps / width 20 = 15 segments a policy, and each segment either inserts
    // (count 1) or credits one KB segment (count + 1)
    const std::int64_t policies = 16 + 3 * 8;
    CHECK(connection.query_int("SELECT sum(count) FROM kb_segment") == policies * 15);
    CHECK(connection.query_int("SELECT policies FROM kb_source") == policies);
    CHECK(connection.query_int("SELECT count(*) FROM kb_segment WHERE last_generation % 2 != 0") == 0);
    // cumulated rewards add up to the observed policies' rewards, 15 segments each
    auto sums = connection.prepare(
        "SELECT (SELECT sum(cum_reward) FROM kb_segment), "
        "(SELECT 15 * sum(reward) FROM individual WHERE generation % 2 = 0)");
    REQUIRE(sums.step());
    CHECK(sums.column_double(0) == Approx(sums.column_double(1)).margin(1e-9));
    // stored packed (fewer bytes than float32), read back by SQL as the 20 x 15 float32 values
    CHECK(connection.query_int("SELECT max(length(segment_values)) FROM kb_segment") < 20 * 15 * 4);
    CHECK(connection.query_int(
              "SELECT min(length(segment_floats(segment_values, 20, 15))) FROM kb_segment") == 20 * 15 * 4);
}

TEST_CASE("a run with a knowledge base is identical across threads and stop and resume", "[exp][kb][determinism]") {
    test::TempDir dir;
    write_config(dir, kTinyKbConfig);
    exp::run_evolve(options_for(dir, "a.db", 1));
    exp::run_evolve(options_for(dir, "b.db", 2));
    auto first = options_for(dir, "c.db", 2);
    first.generations = 3;
    exp::run_evolve(first);
    auto second = options_for(dir, "c.db", 1);
    second.resume = true;
    second.generations = 6;
    exp::run_evolve(second);
    const auto a = test::file_digest(dir / "a.db");
    CHECK(test::file_digest(dir / "b.db") == a);
    CHECK(test::file_digest(dir / "c.db") == a);
}
