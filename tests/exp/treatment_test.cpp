// The treatments as evolve applies them: runs shaped by hand-made KBs whose
// r_max is known without running the code under test. The treatments' own
// rules (names, objectives, the sum bonus) are tested in tests/runs.
#include <catch2/catch.hpp>
#include <cmath>
#include <set>

#include "core/rng.hpp"
#include "db/database.hpp"
#include "db/digest.hpp"
#include "db/kb_store.hpp"
#include "kb/knowledge_base.hpp"
#include "kb/oracle.hpp"
#include "runs/replay.hpp"
#include "sim/episode.hpp"
#include "sim/sensors.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;

namespace {

constexpr double kBall = 1.0 / 24.0;  // one ball of 24 (8 balls x 3 starts)

// A KB of width-20, 15-channel segments: one all-zero segment with average
// `near`, one with every value 5 (further than any robot behaviour, whose
// values lie in [0, 1]) with average `far`. Under match = nearest every
// policy segment matches the zero segment, so r_max = near for every policy.
kb::KnowledgeBase two_segment_kb(double near, double far, kb::Match match = kb::Match::nearest,
                                 std::size_t channels = 15, std::size_t width = 20) {
    kb::KbParams params;
    params.segment_width = width;
    params.channels = channels;
    params.delta = 1.0;
    params.match = match;
    kb::KnowledgeBase base(params);
    const auto source = base.add_source("hand");
    const std::vector<float> zeros(params.dim(), 0.0f);
    const std::vector<float> fives(params.dim(), 5.0f);
    base.observe(kb::as_segments(zeros, params.dim()), near, {source, 0});
    base.observe(kb::as_segments(fives, params.dim()), far, {source, 0});
    return base;
}

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
        const auto nearest = ::kbtest::oracle_nearest(values, dim, behaviour.data() + s * dim);
        REQUIRE(nearest);
        r_max = std::max(r_max, base.record(nearest->first).average());
    }
    return r_max;
}

void write_kb(const std::filesystem::path& path, const kb::KnowledgeBase& kb,
              std::optional<std::uint64_t> randomized_seed = std::nullopt) {
    auto connection = db::open_database(path, db::OpenMode::create);
    db::Transaction transaction(connection);
    db::insert_kb(connection, "hand", kb, randomized_seed);
    transaction.commit();
}

const char* kTarget = R"({
  "task": {"kind": "target", "steps_per_start": 200, "starts": 3},
  "ea": {"population_size": 8, "generations": 2},
  "seed": 11
})";

struct Row {
    double reward, fitness, diversity;
    std::optional<double> shaping;
};

std::vector<Row> individuals(const std::filesystem::path& path) {
    auto connection = db::open_database(path, db::OpenMode::read_only);
    auto statement = connection.prepare("SELECT reward, fitness, diversity, shaping FROM individual ORDER BY id");
    std::vector<Row> rows;
    while (statement.step()) {
        Row row{statement.column_double(0), statement.column_double(1), statement.column_double(2), std::nullopt};
        if (statement.column_type(3) != db::Statement::Type::null) row.shaping = statement.column_double(3);
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

test::CliResult evolve(const test::TempDir& dir, const std::string& db, const std::vector<std::string>& extra) {
    std::vector<std::string> args{"evolve", "--config", (dir / "t.json").string(), "--db", (dir / db).string(),
                                  "--threads", "2", "--quiet"};
    args.insert(args.end(), extra.begin(), extra.end());
    return test::run_cli(args);
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
        REQUIRE(row.shaping);
        CHECK(*row.shaping == 0.2);
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
    auto rows = connection.prepare("SELECT id, reward, fitness, shaping FROM individual ORDER BY id");
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
        REQUIRE(row.shaping);
        CHECK(*row.shaping == Approx(0.3).epsilon(1e-15));
    }
    // the survivors were selected on three objectives
    const auto objectives = run_text(dir / "mo.db",
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
        CHECK(!plain[k].shaping);
        REQUIRE(none[k].shaping);
        CHECK(*none[k].shaping == 0.2);
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
    REQUIRE(evolve(dir, "sr.db", {"--kb", (dir / "rand.db").string(), "--treatment", "sum-rand"}).exit_code == 0);
    // the randomized averages by the documented rule (KnowledgeBase::randomized), not by it:
    // segment i gets the i-th draw of Rng(seed, 0, 0, Purpose::kb_randomize)
    Rng draws(7, 0, 0, Purpose::kb_randomize);
    const double near = draws.uniform();
    const double top = std::max(near, draws.uniform());
    for (const auto& row : individuals(dir / "sr.db")) {
        REQUIRE(row.shaping);
        // the zero segment's randomized average, normalised by the randomized KB's best
        CHECK(*row.shaping == near);
        CHECK(row.fitness == Approx(row.reward + near / top * kBall * (1.0 - 1.0 / 1024)).epsilon(1e-14));
    }
    CHECK(run_text(dir / "sr.db", "SELECT treatment FROM run") == "sum-rand");
    auto kb_connection = db::open_database(dir / "rand.db", db::OpenMode::read_only);
    const auto stored = db::load_kb(kb_connection);
    CHECK(run_text(dir / "sr.db", "SELECT json_extract(config, '$.transfer.kb_digest') FROM run") ==
          db::kb_digest(stored.kb, stored.randomized_seed));
    REQUIRE(evolve(dir, "mr.db", {"--kb", (dir / "rand.db").string(), "--treatment", "mo-rand"}).exit_code == 0);
}

TEST_CASE("bad transfer input: one line, exit 2, no run file", "[exp][treatment][cli][errors]") {
    test::TempDir dir;
    test::write_file(dir / "t.json", kTarget);
    write_kb(dir / "kb.db", two_segment_kb(0.2, 0.8));
    write_kb(dir / "rand.db", two_segment_kb(0.2, 0.8).randomized(3), 3);
    write_kb(dir / "c12.db", two_segment_kb(0.2, 0.8, kb::Match::nearest, 12));
    write_kb(dir / "wide.db", two_segment_kb(0.2, 0.8, kb::Match::nearest, 15, 400));
    const std::string kb = (dir / "kb.db").string();
    struct Case {
        std::vector<std::string> args;
        std::string message;
    };
    const std::vector<Case> cases = {
        {{"--kb", kb, "--treatment", "best"}, "--treatment must be one of"},
        {{"--treatment", "sum"}, "needs a knowledge base"},
        {{"--kb", kb, "--treatment", "sum-rand"}, "needs a randomized knowledge base"},
        {{"--kb", (dir / "rand.db").string(), "--treatment", "mo"}, "use treatment mo-rand"},
        {{"--kb", (dir / "c12.db").string(), "--treatment", "sum"}, "12 channels per step"},
        {{"--kb", (dir / "wide.db").string(), "--treatment", "sum"}, "400 steps wide"},
    };
    for (const auto& c : cases) {
        INFO(c.message);
        const auto result = evolve(dir, "bad.db", c.args);
        CHECK(result.exit_code == 2);
        REQUIRE(result.err_lines().size() == 1);
        CHECK_THAT(result.err, Contains(c.message));
        CHECK(!std::filesystem::exists(dir / "bad.db"));
    }
    // a KB file that is not there is a runtime failure (exit 1), also before anything is written
    const auto missing = evolve(dir, "bad.db", {"--kb", (dir / "missing.db").string(), "--treatment", "sum"});
    CHECK(missing.exit_code == 1);
    CHECK_THAT(missing.err, Contains("missing.db"));
    CHECK(!std::filesystem::exists(dir / "bad.db"));
}

TEST_CASE("a shaped run resumes to the digest of an uninterrupted one and refuses another KB", "[exp][treatment][cli][resume]") {
    test::TempDir dir;
    test::write_file(dir / "t.json", kTarget);
    write_kb(dir / "kb.db", two_segment_kb(0.2, 0.8, kb::Match::within_delta));
    write_kb(dir / "other.db", two_segment_kb(0.1, 0.8));
    const std::string kb = (dir / "kb.db").string();
    REQUIRE(evolve(dir, "whole.db", {"--kb", kb, "--treatment", "mo", "--generations", "4"}).exit_code == 0);
    REQUIRE(evolve(dir, "parts.db", {"--kb", kb, "--treatment", "mo", "--generations", "2"}).exit_code == 0);
    // the KB and treatment come back from the run file when not given again
    REQUIRE(evolve(dir, "parts.db", {"--resume", "--generations", "4"}).exit_code == 0);
    auto whole = db::open_database(dir / "whole.db", db::OpenMode::read_only);
    auto parts = db::open_database(dir / "parts.db", db::OpenMode::read_only);
    CHECK(db::run_digest(whole) == db::run_digest(parts));

    const auto refused = evolve(dir, "parts.db",
                                {"--resume", "--generations", "6", "--kb", (dir / "other.db").string()});
    CHECK(refused.exit_code == 2);
    CHECK_THAT(refused.err, Contains("differs from the one the run was started with"));
}
