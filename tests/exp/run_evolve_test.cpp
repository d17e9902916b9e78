// run_evolve (lib/exp/run_evolve.cpp): what it checks before a run file is
// written or resumed (the config, the run file, the shaping KB and treatment)
// and what it refuses on a resume, in process and through stepstone evolve.
#include <catch2/catch.hpp>

#include "core/error.hpp"
#include "db/database.hpp"
#include "db/digest.hpp"
#include "exp/evolution.hpp"
#include "exp/shaped_runs.hpp"
#include "exp/tiny_run.hpp"
#include "support/db_files.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;
using exptest::evolve;
using exptest::kTarget;
using exptest::kTinyConfig;
using exptest::options_for;
using exptest::two_segment_kb;
using exptest::write_config;
using exptest::write_kb;

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
    CHECK_THROWS_WITH(exp::run_evolve(resume),
                      Contains("run.db: the config differs from the run's at ea.population_size"));
    CHECK(test::read_file(dir / "run.db") == before);

    // an existing file is not replaced without force; the message points to resume first, naming
    // the library's options (the CLI spells them as its flags)
    auto again = options_for(dir, "run.db", 1);
    CHECK_THROWS_WITH(
        exp::run_evolve(again),
        Contains("run.db: already exists; continue it with `resume` (or replace it with `force`)"));
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

TEST_CASE("a shaped run resumes to the digest of an uninterrupted one and refuses another KB",
          "[exp][treatment][cli][resume]") {
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

    const auto refused =
        evolve(dir, "parts.db", {"--resume", "--generations", "6", "--kb", (dir / "other.db").string()});
    CHECK(refused.exit_code == 2);
    CHECK_THAT(refused.err, Contains("differs from the one the run was started with"));
}
