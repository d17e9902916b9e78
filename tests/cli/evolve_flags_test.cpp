// The command line a campaign gives a child `stepstone evolve` is the inverse
// of evolve's parser: the child reads back the very options the campaign made.

#include "evolve_flags.hpp"

#include <catch2/catch.hpp>
#include <filesystem>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "exp/campaign/campaign_runner.hpp"
#include "exp/mpi_evolve.hpp"

using namespace stepstone;

namespace {

// what `stepstone evolve ARGS` hands the engine
exp::EvolveOptions parse(const std::vector<std::string>& args) {
    CLI::App app;
    auto* cmd = app.add_subcommand("evolve");
    app::EvolveFlags flags;
    app::add_evolve_flags(*cmd, flags);
    std::vector<std::string> reversed(args.rbegin(), args.rend());  // CLI11 takes them last first
    app.parse(reversed);
    return app::evolve_options(flags);
}

void check_same(const exp::EvolveOptions& a, const exp::EvolveOptions& b) {
    CHECK(a.config_path == b.config_path);
    CHECK(a.db_path == b.db_path);
    CHECK(a.seed == b.seed);
    CHECK(a.generations == b.generations);
    CHECK(a.retain == b.retain);
    CHECK(a.treatment == b.treatment);
    CHECK(a.kb == b.kb);
    CHECK(a.kb_name == b.kb_name);
    CHECK(a.seed_from == b.seed_from);
    CHECK(a.seed_with == b.seed_with);
    CHECK(a.seed_count == b.seed_count);
    CHECK(a.threads == b.threads);
    CHECK(a.mpi == b.mpi);
    CHECK(a.stop_on_signals == b.stop_on_signals);
    CHECK(a.resume == b.resume);
    CHECK(a.allow_config_change == b.allow_config_change);
    CHECK(a.force == b.force);
    CHECK(a.progress == b.progress);
}

}  // namespace

TEST_CASE("evolve's parser reads evolve_command_line back as the options it was made from", "[cli]") {
    SECTION("a campaign's shaped target run, resumed") {
        exp::RunLaunch launch;
        launch.config = "camp/config/target.json";
        launch.db = "camp/target/sum-rand/seed-7.db";
        launch.seed = 7;
        launch.generations = 40;
        launch.threads = 2;
        launch.resume = true;
        launch.kb = "camp/kb/kb-rand.db";
        launch.treatment = runs::Treatment::sum_rand;
        const auto options = launch.evolve_options();
        const auto args = app::evolve_command_line(options);
        check_same(parse(args), options);
        // written out by hand: the flags a reader of a campaign's process list sees
        CHECK(args == std::vector<std::string>{"evolve", "--db=camp/target/sum-rand/seed-7.db",
                                               "--config=camp/config/target.json", "--seed=7",
                                               "--generations=40", "--threads=2", "--kb=camp/kb/kb-rand.db",
                                               "--treatment=sum-rand", "--resume", "--quiet"});
    }
    SECTION("a campaign's seeded and shaped target run") {
        exp::RunLaunch launch;
        launch.config = "camp/config/target.json";
        launch.db = "camp/target/seed-sum/seed-2.db";
        launch.seed = 2;
        launch.generations = 10;
        launch.threads = 1;
        launch.kb = "camp/kb/kb.db";
        launch.treatment = runs::Treatment::sum;
        launch.seed_from = "camp/source/seed-1.db";
        launch.seed_with = runs::SeedWith::front;
        launch.seed_count = 6;
        const auto options = launch.evolve_options();
        const auto args = app::evolve_command_line(options);
        check_same(parse(args), options);
        CHECK(args == std::vector<std::string>{"evolve", "--db=camp/target/seed-sum/seed-2.db",
                                               "--config=camp/config/target.json", "--seed=2",
                                               "--generations=10", "--threads=1", "--kb=camp/kb/kb.db",
                                               "--treatment=sum", "--seed-from=camp/source/seed-1.db",
                                               "--seed-with=front", "--seed-count=6", "--quiet"});
    }
    SECTION("every option that has a flag, at values a parser could misread") {
        exp::EvolveOptions options;
        options.config_path = "-odd name=1.json";  // a dash first, a space and an equals sign
        options.db_path = "--db";
        options.seed = static_cast<std::uint64_t>(runs::kMaxSeed);
        options.generations = 0;
        options.retain = runs::Retain::all;
        options.treatment = runs::Treatment::mo;
        options.kb = "kb dir/kb.db";
        options.kb_name = "seed-1";
        options.seed_from = "-source run.db";
        options.seed_with = runs::SeedWith::best;
        options.seed_count = 1000000000;
        options.threads = 1024;
        options.allow_config_change = true;
        options.force = true;
        check_same(parse(app::evolve_command_line(options)), options);
    }
    SECTION("the defaults: no flag but --db") {
        exp::EvolveOptions options;
        options.db_path = "run.db";
        options.resume = true;
        options.retain = runs::Retain::front;
        const auto args = app::evolve_command_line(options);
        check_same(parse(args), options);
        CHECK(args == std::vector<std::string>{"evolve", "--db=run.db", "--retain=front", "--resume"});
    }
}

TEST_CASE("evolve's seed flags refuse a count below 1, a seeded treatment name and an unknown with",
          "[cli][seed][errors]") {
    CHECK_THROWS_WITH(parse({"evolve", "--db=r.db", "--seed-from=s.db", "--seed-count=0"}),
                      Catch::Matchers::Contains("--seed-count must be an integer from 1"));
    CHECK_THROWS_WITH(parse({"evolve", "--db=r.db", "--seed-from=s.db", "--seed-count=-3"}),
                      Catch::Matchers::Contains("got -3"));
    CHECK_THROWS_WITH(parse({"evolve", "--db=r.db", "--treatment=seed-sum"}),
                      Catch::Matchers::Contains("with treatment sum"));
    CHECK_THROWS(parse({"evolve", "--db=r.db", "--seed-from=s.db", "--seed-with=all"}));
}

TEST_CASE("options that no evolve flag can carry have no command line", "[cli]") {
    exp::EvolveOptions options;
    options.db_path = "run.db";
    options.stop_on_signals = false;  // a worker rank's
    CHECK_THROWS_AS(app::evolve_command_line(options), ConfigError);
    options.stop_on_signals = true;
    options.progress = ProgressMode::bar;
    CHECK_THROWS_AS(app::evolve_command_line(options), ConfigError);
}
