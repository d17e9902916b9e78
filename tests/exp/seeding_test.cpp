// Seeding (lib/exp/seeding.cpp, transfer.seed, evolve --seed-from): generation 0
// of a target run holds exactly the source run's policies that `with` and
// `count` pick, the rest drawn as an unseeded run draws them; a seeded run
// resumes bit for bit, whatever the threads, even when stopped inside
// generation 0; a different source is refused on resume; bad input writes
// nothing. Real files, made by the stepstone binary on tiny configs.
#include <algorithm>
#include <catch2/catch.hpp>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "db/database.hpp"
#include "evo/pareto.hpp"
#include "exp/shaped_runs.hpp"
#include "support/db_files.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;

namespace seedingtest {

namespace fs = std::filesystem;

// a tiny finished source run: population 8, 3 generations of one 200-step start
constexpr const char* kSource = R"({
  "task": {"kind": "source", "steps_per_start": 200, "starts": 1},
  "ea": {"population_size": 8, "generations": 3},
  "seed": 5
})";

// a target run whose generation 0 lasts about a second (800 full-length policies and
// their 320,000 distances), so that a kill lands inside it
constexpr const char* kSlowStart = R"({
  "task": {"kind": "target", "steps_per_start": 2000, "starts": 1, "still_limit": 100000000},
  "ea": {"population_size": 8, "generations": 3, "initial_multiplier": 100},
  "seed": 13
})";

test::CliResult make_source(const test::TempDir& dir, const std::string& name, int seed = 5) {
    test::write_file(dir / "s.json", kSource);
    return test::run_cli({"evolve", "--config", (dir / "s.json").string(), "--db", (dir / name).string(),
                          "--seed", std::to_string(seed), "--threads", "1", "--quiet"});
}

struct Policy {
    std::int64_t id = 0;
    double reward = 0;
    nlohmann::json genome;
    std::vector<double> objectives;
};

std::vector<Policy> checkpoint_policies(const fs::path& run) {
    auto connection = db::open_database(run, db::OpenMode::read_only);
    auto select = connection.prepare("SELECT state FROM checkpoint");
    REQUIRE(select.step());
    std::vector<Policy> out;
    const auto state = nlohmann::json::parse(select.column_text(0));
    for (const auto& m : state.at("population")) {
        out.push_back({m.at("id").get<std::int64_t>(), m.at("reward").get<double>(), m.at("genome"),
                       m.at("objectives").get<std::vector<double>>()});
    }
    return out;
}

// what a seed of `with` must hold, computed from the source's rows by hand: highest reward
// first, the lower id on ties, at most `count`
std::vector<nlohmann::json> expected_seeds(const fs::path& source, const std::string& with,
                                           std::size_t count) {
    std::vector<Policy> policies;
    if (with == "best") {
        auto connection = db::open_database(source, db::OpenMode::read_only);
        auto select = connection.prepare(
            "SELECT i.id, i.reward, g.genome FROM genome g JOIN individual i ON i.id = g.individual_id");
        while (select.step()) {
            policies.push_back({select.column_int(0),
                                select.column_double(1),
                                nlohmann::json::parse(select.column_text(2)),
                                {}});
        }
    } else {
        const auto population = checkpoint_policies(source);
        for (const auto& a : population) {
            bool dominated = false;
            for (const auto& b : population)
                dominated = dominated || evo::dominates(b.objectives, a.objectives);
            if (with == "population" || !dominated) policies.push_back(a);
        }
    }
    std::sort(policies.begin(), policies.end(), [](const Policy& a, const Policy& b) {
        return a.reward != b.reward ? a.reward > b.reward : a.id < b.id;
    });
    std::vector<nlohmann::json> genomes;
    for (std::size_t k = 0; k < policies.size() && k < count; ++k) genomes.push_back(policies[k].genome);
    return genomes;
}

// the stored genomes of generation 0's individuals, by id (every one with --retain all)
std::vector<nlohmann::json> generation0_genomes(const fs::path& run) {
    auto connection = db::open_database(run, db::OpenMode::read_only);
    auto select = connection.prepare(
        "SELECT g.genome FROM genome g JOIN individual i ON i.id = g.individual_id WHERE i.generation = 0 "
        "ORDER BY i.id");
    std::vector<nlohmann::json> out;
    while (select.step()) out.push_back(nlohmann::json::parse(select.column_text(0)));
    return out;
}

struct StoredRun {
    std::string treatment;
    nlohmann::json config;
};

StoredRun stored_run(const fs::path& run) {
    auto connection = db::open_database(run, db::OpenMode::read_only);
    auto select = connection.prepare("SELECT treatment, config FROM run");
    REQUIRE(select.step());
    return {select.column_text(0), nlohmann::json::parse(select.column_text(1))};
}

// evolve of dir/`config` into dir/`db`, quiet, followed by `extra`, on 2 threads unless it names them
test::CliResult evolve_config(const test::TempDir& dir, const std::string& config, const std::string& db,
                              const std::vector<std::string>& extra) {
    std::vector<std::string> args{"evolve", "--config",          (dir / config).string(),
                                  "--db",   (dir / db).string(), "--quiet"};
    args.insert(args.end(), extra.begin(), extra.end());
    if (std::find(extra.begin(), extra.end(), "--threads") == extra.end()) {
        args.push_back("--threads");
        args.push_back("2");
    }
    return test::run_cli(args);
}

// evolve_config of dir/t.json
test::CliResult evolve(const test::TempDir& dir, const std::string& db,
                       const std::vector<std::string>& extra) {
    return evolve_config(dir, "t.json", db, extra);
}

void run_sql(const fs::path& file, const char* sql) {
    auto connection = db::open_database(file, db::OpenMode::read_write);
    connection.exec(sql);
}

using exptest::kTarget;

// the cases too, so that their helpers hide the other files' of this unity build

TEST_CASE("seeded generation 0 holds the source's policies of each kind, then random ones as unseeded",
          "[exp][seed][cli]") {
    test::TempDir dir;
    test::write_file(dir / "t.json", kTarget);
    REQUIRE(make_source(dir, "source.db").exit_code == 0);
    const auto source = dir / "source.db";
    REQUIRE(evolve(dir, "plain.db", {"--retain", "all", "--generations", "0"}).exit_code == 0);
    const auto plain = generation0_genomes(dir / "plain.db");
    REQUIRE(plain.size() == 16);  // 2 x 8 random genomes

    struct Case {
        std::string with;
        std::vector<std::string> count;
        std::size_t at_most;
    };
    for (const Case& c : {Case{"population", {}, 8}, Case{"front", {}, 8},
                          Case{"best", {"--seed-count", "3"}, 3}, Case{"best", {}, 8}}) {
        INFO(c.with << " " << c.at_most);
        const std::string name = "seeded-" + c.with + std::to_string(c.at_most) + ".db";
        std::vector<std::string> args{"--retain",    "all",           "--generations", "0",
                                      "--seed-from", source.string(), "--seed-with",   c.with};
        args.insert(args.end(), c.count.begin(), c.count.end());
        const auto result = evolve(dir, name, args);
        INFO(result.err);
        REQUIRE(result.exit_code == 0);
        const auto expected = expected_seeds(source, c.with, c.at_most);
        REQUIRE(!expected.empty());
        // the source's last first front holds fewer than the population: the rest is filled up
        if (c.with == "front") CHECK(expected.size() < 8);
        const auto genomes = generation0_genomes(dir / name);
        REQUIRE(genomes.size() == 16);
        // the seeds first, in order, exactly as the source stored them
        for (std::size_t k = 0; k < expected.size(); ++k) CHECK(genomes[k] == expected[k]);
        // then the random genomes an unseeded run of the same seed draws at those places
        for (std::size_t k = expected.size(); k < genomes.size(); ++k) CHECK(genomes[k] == plain[k]);

        const auto run = stored_run(dir / name);
        CHECK(run.treatment == "seed");
        const auto& seed = run.config.at("transfer").at("seed");
        CHECK(seed.at("from") == fs::absolute(source).lexically_normal().string());
        CHECK(seed.at("with") == c.with);
        CHECK(seed.at("count") == (c.count.empty() ? 8 : 3));
        CHECK(seed.at("digest") == test::file_digest(source));
        CHECK(!run.config.at("transfer").contains("kb"));
    }

    // with the default retention the seeds are stored too: a seeded run keeps what it started from
    REQUIRE(evolve(dir, "front-kept.db", {"--generations", "0", "--seed-from", source.string()}).exit_code ==
            0);
    const auto kept = generation0_genomes(dir / "front-kept.db");
    const auto expected = expected_seeds(source, "population", 8);
    REQUIRE(kept.size() >= expected.size());
    for (std::size_t k = 0; k < expected.size(); ++k) CHECK(kept[k] == expected[k]);
}

TEST_CASE("a seeded run stopped and resumed equals an uninterrupted one, whatever the threads",
          "[exp][seed][resume][determinism][cli]") {
    test::TempDir dir;
    test::write_file(dir / "t.json", kTarget);
    REQUIRE(make_source(dir, "source.db").exit_code == 0);
    const std::string source = (dir / "source.db").string();

    SECTION("stopped after generation 1; the source gone by the resume") {
        REQUIRE(evolve(dir, "whole.db", {"--seed-from", source, "--generations", "4"}).exit_code == 0);
        REQUIRE(evolve(dir, "parts.db", {"--seed-from", source, "--generations", "1", "--threads", "1"})
                    .exit_code == 0);
        fs::rename(dir / "source.db", dir / "moved.db");
        // no seed flag: the stored config seeds nothing more, and the source is not looked for
        const auto resumed = evolve(dir, "parts.db", {"--resume", "--generations", "4", "--threads", "1"});
        INFO(resumed.err);
        REQUIRE(resumed.exit_code == 0);
        CHECK(test::file_digest(dir / "parts.db") == test::file_digest(dir / "whole.db"));
        CHECK(stored_run(dir / "parts.db").treatment == "seed");
    }

    SECTION("killed inside generation 0: the resume seeds it again") {
        test::write_file(dir / "slow.json", kSlowStart);
        const auto run = [&](const std::string& db, std::vector<std::string> extra) {
            std::vector<std::string> args{"evolve",
                                          "--config",
                                          (dir / "slow.json").string(),
                                          "--db",
                                          (dir / db).string(),
                                          "--seed-from",
                                          source,
                                          "--seed-with",
                                          "best",
                                          "--seed-count",
                                          "5",
                                          "--quiet"};
            args.insert(args.end(), extra.begin(), extra.end());
            return args;
        };
        REQUIRE(test::run_cli(run("whole.db", {"--threads", "2"})).exit_code == 0);
        const auto killed = dir / "killed.db";
        // the run row written, generation 0 not yet committed
        REQUIRE(test::run_cli_killed_when(run("killed.db", {"--threads", "1"}),
                                          [&] { return test::generations_done(killed, -2) == -1; }));
        REQUIRE(test::generations_done(killed) == -1);

        // the source is needed again: without it the resume is refused, the file left as it was
        fs::rename(dir / "source.db", dir / "moved.db");
        const auto refused =
            test::run_cli({"evolve", "--db", killed.string(), "--resume", "--threads", "1", "--quiet"});
        CHECK(refused.exit_code != 0);
        CHECK(refused.err_lines().size() == 1);
        CHECK_THAT(refused.err, Contains("source.db: no such file"));
        CHECK(test::generations_done(killed) == -1);
        fs::rename(dir / "moved.db", dir / "source.db");

        const auto resumed =
            test::run_cli({"evolve", "--db", killed.string(), "--resume", "--threads", "1", "--quiet"});
        INFO(resumed.err);
        REQUIRE(resumed.exit_code == 0);
        CHECK(test::file_digest(killed) == test::file_digest(dir / "whole.db"));
    }
}

TEST_CASE("resuming a seeded run from a different source is refused naming both digests",
          "[exp][seed][resume][errors][cli]") {
    test::TempDir dir;
    test::write_file(dir / "t.json", kTarget);
    REQUIRE(make_source(dir, "source.db").exit_code == 0);
    REQUIRE(make_source(dir, "other.db", 6).exit_code == 0);
    const auto source = dir / "source.db";
    const std::string first = test::file_digest(source), second = test::file_digest(dir / "other.db");
    REQUIRE(first != second);
    REQUIRE(evolve(dir, "run.db", {"--seed-from", source.string(), "--generations", "1"}).exit_code == 0);
    const std::string before = test::read_file(dir / "run.db");

    // another run in the source's place, or named by the flag
    for (const bool by_flag : {false, true}) {
        INFO("by flag " << by_flag);
        std::vector<std::string> args{"--resume", "--generations", "2"};
        if (by_flag) {
            args.push_back("--seed-from");
            args.push_back((dir / "other.db").string());
        } else {
            fs::copy_file(dir / "other.db", source, fs::copy_options::overwrite_existing);
        }
        const auto refused = evolve(dir, "run.db", args);
        CHECK(refused.exit_code == 2);
        CHECK(refused.err_lines().size() == 1);
        CHECK_THAT(refused.err, Contains(first) && Contains(second));
        CHECK(test::read_file(dir / "run.db") == before);
    }
}

TEST_CASE("bad seed input: one line, a non-zero exit, no run file", "[exp][seed][errors][cli]") {
    test::TempDir dir;
    test::write_file(dir / "t.json", kTarget);
    REQUIRE(make_source(dir, "source.db").exit_code == 0);
    const std::string source = (dir / "source.db").string();
    // an unfinished run, and runs whose networks are not the robot's
    for (const char* name : {"unfinished.db", "inputs.db", "genome.db"}) fs::copy_file(source, dir / name);
    run_sql(dir / "unfinished.db", "UPDATE run SET status = 'running'");
    run_sql(dir / "inputs.db", "UPDATE run SET config = json_set(config, '$.dnn.inputs', 10)");
    run_sql(dir / "genome.db",
            "UPDATE checkpoint SET state = json_set(state, '$.population[0].genome.outputs', 2, "
            "'$.population[1].genome.outputs', 2, '$.population[2].genome.outputs', 2, "
            "'$.population[3].genome.outputs', 2, '$.population[4].genome.outputs', 2, "
            "'$.population[5].genome.outputs', 2, '$.population[6].genome.outputs', 2, "
            "'$.population[7].genome.outputs', 2)");
    exptest::write_kb(dir / "kb.db", exptest::two_segment_kb(0.2, 0.8));
    test::write_file(dir / "big.json", R"({"task": {"kind": "target", "steps_per_start": 200, "starts": 1},
                                          "ea": {"population_size": 12}, "seed": 1})");
    test::write_file(
        dir / "count0.json",
        R"({"task": {"kind": "target"}, "transfer": {"seed": {"from": "source.db", "count": 0}}})");
    test::write_file(
        dir / "with.json",
        R"({"task": {"kind": "target"}, "transfer": {"seed": {"from": "source.db", "with": "all"}}})");
    test::write_file(dir / "name.json", R"({"task": {"kind": "target"}, "transfer": {"treatment": "seed"}})");
    struct Case {
        std::vector<std::string> args;
        std::string message;
        std::string config = "t.json";
    };
    const std::vector<Case> cases = {
        {{"--seed-from", (dir / "missing.db").string()}, "missing.db: no such file"},
        {{"--seed-from", (dir / "unfinished.db").string()}, "the source run is not finished"},
        {{"--seed-from", (dir / "inputs.db").string()}, "10 inputs and 3 outputs (13 behaviour channels)"},
        {{"--seed-from", (dir / "genome.db").string()}, "network has 12 inputs and 2 outputs"},
        {{"--seed-from", (dir / "kb.db").string()}, "holds no run"},
        {{"--seed-from", source}, "the source population holds 8", "big.json"},
        {{"--seed-from", source, "--seed-count", "0"}, "--seed-count must be an integer from 1"},
        {{"--seed-from", source, "--seed-count", "-2"}, "--seed-count must be an integer from 1"},
        {{"--seed-from", source, "--seed-with", "all"}, "--seed-with"},
        {{"--seed-with", "front"}, "--seed-with needs a seed source (--seed-from or transfer.seed.from)"},
        {{"--seed-count", "3"}, "--seed-count needs a seed source"},
        {{"--treatment", "seed-sum"}, "with treatment sum"},
        {{}, "transfer.seed.count must be >= 1, got 0", "count0.json"},
        {{}, "transfer.seed.with", "with.json"},
        {{}, "with treatment none", "name.json"},
    };
    for (const auto& c : cases) {
        INFO(c.message);
        const auto result = evolve_config(dir, c.config, "bad.db", c.args);
        CHECK(result.exit_code != 0);
        CHECK(result.err_lines().size() == 1);
        CHECK_THAT(result.err, Contains(c.message));
        CHECK(!fs::exists(dir / "bad.db"));
    }
    // a population of another size is fine for front and best
    CHECK(evolve_config(dir, "big.json", "big.db",
                        {"--seed-from", source, "--seed-with", "best", "--generations", "0"})
              .exit_code == 0);
}

TEST_CASE("a seeded run can be shaped too: seed-sum, bit for bit across threads",
          "[exp][seed][treatment][cli]") {
    test::TempDir dir;
    test::write_file(dir / "t.json", kTarget);
    REQUIRE(make_source(dir, "source.db").exit_code == 0);
    exptest::write_kb(dir / "kb.db", exptest::two_segment_kb(0.2, 0.8));
    const std::vector<std::string> args{"--kb",        (dir / "kb.db").string(),     "--treatment", "sum",
                                        "--seed-from", (dir / "source.db").string(), "--retain",    "all"};
    auto one = args, two = args;
    one.insert(one.end(), {"--threads", "1"});
    REQUIRE(evolve(dir, "one.db", one).exit_code == 0);
    REQUIRE(evolve(dir, "two.db", two).exit_code == 0);
    CHECK(test::file_digest(dir / "one.db") == test::file_digest(dir / "two.db"));
    const auto run = stored_run(dir / "one.db");
    CHECK(run.treatment == "seed-sum");
    CHECK(run.config.at("transfer").at("treatment") == "sum");
    CHECK(run.config.at("transfer").contains("kb_digest"));
    CHECK(run.config.at("transfer").at("seed").at("digest") == test::file_digest(dir / "source.db"));
    const auto expected = expected_seeds(dir / "source.db", "population", 8);
    const auto genomes = generation0_genomes(dir / "one.db");
    REQUIRE(genomes.size() == 16);
    for (std::size_t k = 0; k < expected.size(); ++k) CHECK(genomes[k] == expected[k]);
    // every policy shaped: r_max recorded, the fitness above the reward by the sum bonus
    auto connection = db::open_database(dir / "one.db", db::OpenMode::read_only);
    CHECK(connection.query_int("SELECT count(*) FROM individual WHERE r_max IS NULL").value_or(-1) == 0);
    CHECK(connection.query_int("SELECT count(*) FROM individual WHERE fitness <= reward").value_or(-1) == 0);
}

TEST_CASE("scripts/demo-seeds cuts a run to the K policies `with: best` takes, a seed source seeding alike",
          "[exp][seed][cli][script]") {
    test::TempDir dir;
    test::write_file(dir / "t.json", kTarget);
    REQUIRE(make_source(dir, "source.db").exit_code == 0);
    const auto source = dir / "source.db";
    // rewards with ties, so that the cut has both orders to follow: reward, then the lower id
    run_sql(source, "UPDATE individual SET reward = (id % 3) / 24.0");
    const std::string script = std::string(STEPSTONE_SOURCE_DIR) + "/scripts/demo-seeds";
    const auto cut = dir / "cut.db";
    const auto made = test::run_program({script, source.string(), cut.string(), "3"});
    INFO(made.err);
    REQUIRE(made.exit_code == 0);

    // the cut holds exactly the 3 stored genomes the hand-sorted rows give, and no checkpoint
    const auto expected = expected_seeds(source, "best", 3);
    REQUIRE(expected.size() == 3);
    CHECK(expected_seeds(cut, "best", 100) == expected);
    auto connection = db::open_database(cut, db::OpenMode::read_only);
    CHECK(connection.query_int("SELECT count(*) FROM individual").value_or(-1) == 3);
    CHECK(connection.query_int("SELECT count(*) FROM checkpoint").value_or(-1) == 0);
    CHECK(connection.query_int("SELECT count(*) FROM generation").value_or(-1) == 1);

    // seeding from the cut and from the whole run gives one generation 0
    const std::vector<std::string> args{"--retain",    "all",  "--generations", "0",
                                        "--seed-with", "best", "--seed-count",  "3"};
    auto with_source = [&](const fs::path& from) {
        auto all = args;
        all.insert(all.end(), {"--seed-from", from.string()});
        return all;
    };
    REQUIRE(evolve(dir, "from-run.db", with_source(source)).exit_code == 0);
    REQUIRE(evolve(dir, "from-cut.db", with_source(cut)).exit_code == 0);
    CHECK(generation0_genomes(dir / "from-cut.db") == generation0_genomes(dir / "from-run.db"));

    // an existing output is never overwritten; a bad K names itself
    const auto bytes = test::read_file(cut);
    const auto again = test::run_program({script, source.string(), cut.string(), "3"});
    CHECK(again.exit_code != 0);
    CHECK_THAT(again.err, Contains(cut.string() + ": exists"));
    CHECK(test::read_file(cut) == bytes);
    const auto bad = test::run_program({script, source.string(), (dir / "k.db").string(), "zero"});
    CHECK(bad.exit_code != 0);
    CHECK_THAT(bad.err, Contains("K must be a whole number"));
    CHECK_FALSE(fs::exists(dir / "k.db"));
}

}  // namespace seedingtest
