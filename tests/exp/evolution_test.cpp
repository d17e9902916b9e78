// Evolution: one generation at a time (lib/exp/evolution.cpp), through
// run_evolve and stepstone evolve: determinism over threads and resumes, what
// each generation writes, the run's own KB, and the treatments' objectives on
// runs shaped by hand-made KBs whose r_max is known without the code under test.
#include "exp/evolution.hpp"

#include <catch2/catch.hpp>
#include <set>

#include "core/error.hpp"
#include "core/rng.hpp"
#include "db/database.hpp"
#include "db/digest.hpp"
#include "db/kb_store.hpp"
#include "exp/shaped_runs.hpp"
#include "exp/tiny_run.hpp"
#include "kb/oracle.hpp"
#include "runs/replay.hpp"
#include "sim/sensors.hpp"
#include "support/db_files.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using exptest::evolve;
using exptest::kBall;
using exptest::kTarget;
using exptest::kTinyConfig;
using exptest::options_for;
using exptest::two_segment_kb;
using exptest::write_config;
using exptest::write_kb;

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

namespace {

// A KB whose r_max differs from policy to policy: 21 width-20, 15-channel
// segments, every value of segment j equal to j / 20, with averages scrambled
// over j ((8 j mod 21) + 1) / 22, all distinct (8 and 21 are coprime). Under match = nearest a policy
// segment matches the level nearest its mean, so policies that behave
// differently get different r_max.
kb::KnowledgeBase level_kb() {
    kb::KbParams params;
    params.segment_width = 20;
    params.channels = 15;
    params.delta = 0.1;  // the levels lie 0.05 x sqrt(300) = 0.87 apart: each is kept
    params.match = kb::Match::nearest;
    kb::KnowledgeBase base(params);
    const auto source = base.add_source("levels");
    for (int j = 0; j <= 20; ++j) {
        const std::vector<float> level(params.dim(), static_cast<float>(j) / 20.0f);
        base.observe(kb::as_segments(level, params.dim()), ((8 * j) % 21 + 1) / 22.0, {source, 0});
    }
    return base;
}

// The first start's behaviour matrix of stored individual `id` (steps x 15: the
// 12 inputs then the 3 outputs), gathered from what the replay's observer sees
// at each step rather than from the episode's own recording; rows after an
// early stop repeat the last one (docs/simulator.md).
std::vector<float> observed_behaviour(const std::filesystem::path& run, std::int64_t id, std::size_t steps) {
    auto setup = runs::prepare_replay(run, std::to_string(id));
    std::vector<float> rows;
    setup.run([&](const sim::StepView& view) {
        if (view.start != 0) return;
        rows.insert(rows.end(), view.inputs, view.inputs + sim::kInputs);
        rows.insert(rows.end(), view.outputs, view.outputs + sim::kOutputs);
    });
    REQUIRE(rows.size() >= static_cast<std::size_t>(sim::kChannels));
    const std::vector<float> last(rows.end() - sim::kChannels, rows.end());
    while (rows.size() < steps * sim::kChannels) rows.insert(rows.end(), last.begin(), last.end());
    return rows;
}

// r_max by a linear scan (tests/kb/oracle.hpp): the largest average of the KB
// segments nearest to each whole width-20 segment of `behaviour`
double oracle_r_max(const kb::KnowledgeBase& base, const std::vector<float>& behaviour) {
    const std::vector<float> values(base.values().begin(), base.values().end());
    const std::size_t dim = base.params().dim();
    double r_max = 0.0;
    for (std::size_t s = 0; (s + 1) * dim <= behaviour.size(); ++s) {
        const auto nearest = kboracle::oracle_nearest(values, dim, behaviour.data() + s * dim);
        REQUIRE(nearest);
        r_max = std::max(r_max, base.record(nearest->first).average());
    }
    return r_max;
}

struct Row {
    double reward, fitness, diversity;
    std::optional<double> r_max;
};

std::vector<Row> individuals(const std::filesystem::path& path) {
    auto connection = db::open_database(path, db::OpenMode::read_only);
    auto statement =
        connection.prepare("SELECT reward, fitness, diversity, r_max FROM individual ORDER BY id");
    std::vector<Row> rows;
    while (statement.step()) {
        Row row{statement.column_double(0), statement.column_double(1), statement.column_double(2),
                std::nullopt};
        if (statement.column_type(3) != db::Statement::Type::null) row.r_max = statement.column_double(3);
        rows.push_back(row);
    }
    return rows;
}

std::string run_text(const std::filesystem::path& path, const std::string& query) {
    auto connection = db::open_database(path, db::OpenMode::read_only);
    auto statement = connection.prepare(query);
    REQUIRE(statement.step());
    return std::string(statement.column_text(0));
}

}  // namespace

TEST_CASE("evolve sum: every fitness is reward + the hand-computed bonus", "[exp][treatment][cli]") {
    test::TempDir dir;
    test::write_file(dir / "t.json", kTarget);
    write_kb(dir / "kb.db", two_segment_kb(0.2, 0.8));
    const auto result = evolve(dir, "sum.db", {"--kb", (dir / "kb.db").string(), "--treatment", "sum"});
    REQUIRE(result.exit_code == 0);
    // r_max = 0.2 (the zero segment), normalised by the best average 0.8: a quarter of a ball less the margin
    const auto rows = individuals(dir / "sum.db");
    REQUIRE(rows.size() == 16 + 2 * 8);
    for (const auto& row : rows) {
        REQUIRE(row.r_max);
        CHECK(*row.r_max == 0.2);
        CHECK(row.fitness == Approx(row.reward + 0.25 * kBall * (1.0 - 1.0 / 1024)).epsilon(1e-14));
    }
    CHECK(run_text(dir / "sum.db", "SELECT treatment FROM run") == "sum");
    CHECK(run_text(dir / "sum.db", "SELECT json_extract(config, '$.transfer.treatment') FROM run") == "sum");
}

TEST_CASE("evolve sum with a KB whose r_max differs by policy: each policy's r_max is its own behaviour's",
          "[exp][treatment][cli]") {
    test::TempDir dir;
    test::write_file(dir / "t.json", kTarget);
    const auto base = level_kb();
    write_kb(dir / "kb.db", base);
    REQUIRE(evolve(dir, "sum.db", {"--kb", (dir / "kb.db").string(), "--treatment", "sum", "--retain", "all"})
                .exit_code == 0);
    const double top = 21.0 / 22.0;  // the largest of the scrambled averages
    auto connection = db::open_database(dir / "sum.db", db::OpenMode::read_only);
    auto rows = connection.prepare("SELECT id, reward, fitness, r_max FROM individual ORDER BY id");
    std::size_t checked = 0;
    std::set<double> values;
    while (rows.step()) {
        const std::int64_t id = rows.column_int(0);
        const double reward = rows.column_double(1), fitness = rows.column_double(2);
        CAPTURE(id);
        REQUIRE(rows.column_type(3) != db::Statement::Type::null);
        // every policy replayed from its stored genome, its r_max looked up here
        const double expected = oracle_r_max(base, observed_behaviour(dir / "sum.db", id, 200));
        CHECK(rows.column_double(3) == expected);
        CHECK(fitness == Approx(reward + expected / top * kBall * (1.0 - 1.0 / 1024)).epsilon(1e-14));
        values.insert(expected);
        ++checked;
    }
    CHECK(checked == 16 + 2 * 8);
    // enough distinct r_max that a policy given another's lookup is seen
    CHECK(values.size() >= 4);
}

TEST_CASE("evolve mo: r_max is the third objective and fitness stays the reward", "[exp][treatment][cli]") {
    test::TempDir dir;
    test::write_file(dir / "t.json", kTarget);
    write_kb(dir / "kb.db", two_segment_kb(0.3, 0.9));
    REQUIRE(evolve(dir, "mo.db", {"--kb", (dir / "kb.db").string(), "--treatment", "mo"}).exit_code == 0);
    for (const auto& row : individuals(dir / "mo.db")) {
        CHECK(row.fitness == row.reward);
        REQUIRE(row.r_max);
        CHECK(*row.r_max == Approx(0.3).epsilon(1e-15));
    }
    // the survivors were selected on three objectives
    const auto objectives =
        run_text(dir / "mo.db",
                 "SELECT json_array_length(json_extract(state, '$.population[0].objectives')) "
                 "FROM checkpoint");
    CHECK(objectives == "3");
}

TEST_CASE("evolve none: no KB, no shaping, and with a KB r_max is recorded but not used",
          "[exp][treatment][cli]") {
    test::TempDir dir;
    test::write_file(dir / "t.json", kTarget);
    write_kb(dir / "kb.db", two_segment_kb(0.2, 0.8));
    REQUIRE(evolve(dir, "plain.db", {}).exit_code == 0);
    REQUIRE(evolve(dir, "none.db", {"--kb", (dir / "kb.db").string(), "--treatment", "none"}).exit_code == 0);
    const auto plain = individuals(dir / "plain.db");
    const auto none = individuals(dir / "none.db");
    REQUIRE(plain.size() == none.size());
    for (std::size_t k = 0; k < plain.size(); ++k) {
        CHECK(!plain[k].r_max);
        REQUIRE(none[k].r_max);
        CHECK(*none[k].r_max == 0.2);
        // same seed, same objectives: the recorded r_max changed nothing
        CHECK(none[k].fitness == plain[k].fitness);
        CHECK(none[k].diversity == plain[k].diversity);
    }
}

TEST_CASE("rand treatments use the randomized KB and record which", "[exp][treatment][cli]") {
    test::TempDir dir;
    test::write_file(dir / "t.json", kTarget);
    const auto base = two_segment_kb(0.2, 0.8);
    const auto randomized = base.randomized(7);
    write_kb(dir / "kb.db", base);
    write_kb(dir / "rand.db", randomized, 7);
    REQUIRE(evolve(dir, "sr.db", {"--kb", (dir / "rand.db").string(), "--treatment", "sum-rand"}).exit_code ==
            0);
    // the randomized averages by the documented rule (KnowledgeBase::randomized), not by it:
    // segment i gets the i-th draw of Rng(seed, 0, 0, Purpose::kb_randomize)
    Rng draws(7, 0, 0, Purpose::kb_randomize);
    const double near = draws.uniform();
    const double top = std::max(near, draws.uniform());
    for (const auto& row : individuals(dir / "sr.db")) {
        REQUIRE(row.r_max);
        // the zero segment's randomized average, normalised by the randomized KB's best
        CHECK(*row.r_max == near);
        CHECK(row.fitness == Approx(row.reward + near / top * kBall * (1.0 - 1.0 / 1024)).epsilon(1e-14));
    }
    CHECK(run_text(dir / "sr.db", "SELECT treatment FROM run") == "sum-rand");
    auto kb_connection = db::open_database(dir / "rand.db", db::OpenMode::read_only);
    const auto stored = db::load_kb(kb_connection);
    CHECK(run_text(dir / "sr.db", "SELECT json_extract(config, '$.transfer.kb_digest') FROM run") ==
          db::kb_digest(stored.kb, stored.randomized_seed));
    REQUIRE(evolve(dir, "mr.db", {"--kb", (dir / "rand.db").string(), "--treatment", "mo-rand"}).exit_code ==
            0);
}
