// A second arena end to end: a run config naming it evolves (shaped by a KB
// grown in the paper's arena), stores it, renders it and shapes with it; a
// broken arena is refused before any file is written.

#include <catch2/catch.hpp>
#include <cmath>

#include "db/connection.hpp"
#include "images.hpp"
#include "report/arena_figure.hpp"
#include "report/style.hpp"
#include "runs/evolve_config.hpp"
#include "sim/arena_spec.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;
using stepstone::reporttest::rgb;
using stepstone::test::run_cli;
using stepstone::test::TempDir;

namespace {

const std::filesystem::path kArenas = std::filesystem::path(STEPSTONE_SOURCE_DIR) / "examples" / "arenas";

}  // namespace

TEST_CASE("a run config's arena file is read relative to it and stored whole, and the paper's adds no key",
          "[report][arena]") {
    const auto config = runs::EvolveConfig::load(kArenas / "two_rooms_quick.json");
    const auto two_rooms = sim::ArenaSpec::load(kArenas / "two_rooms.json");
    REQUIRE(config.task.arena);
    CHECK(*config.task.arena == two_rooms);
    const auto stored = config.to_json();
    CHECK(stored.at("task").at("arena") == two_rooms.to_json());
    // what a run stores reads back to the same arena, with no file at hand
    CHECK(*runs::EvolveConfig::from_json(stored).task.arena == two_rooms);
    // the paper's arena is the default and leaves the stored config (and so every digest) as it was
    CHECK_FALSE(runs::EvolveConfig{}.to_json()["task"].contains("arena"));
}

TEST_CASE("the two-rooms arena evolves shaped by a paper-arena KB, renders and shapes",
          "[report][arena][cli]") {
    const TempDir dir;
    const auto p = [&](const char* name) { return (dir / name).string(); };
    // a KB grown in the paper's arena by a small source run; "nearest" matches every policy segment, so that
    // the other arena's behaviours (other sensor values) always find one at lookup
    test::write_file(dir / "source.json",
                     R"({"task": {"kind": "source", "steps_per_start": 300, "starts": 1},
                         "ea": {"population_size": 8, "generations": 2},
                         "kb": {"segment_width": 20, "delta": 1.83, "period": 1, "match": "nearest"}})");
    REQUIRE(
        run_cli({"evolve", "--config", p("source.json"), "--db", p("source.db"), "--seed", "1", "--quiet"})
            .exit_code == 0);
    REQUIRE(run_cli({"kb", "randomize", p("source.db"), "--seed", "3", "--out", p("kb.db")}).exit_code == 0);

    const auto config = (kArenas / "two_rooms_quick.json").string();
    const auto run =
        run_cli({"evolve", "--config", config, "--db", p("run.db"), "--seed", "2", "--generations", "2",
                 "--kb", p("kb.db"), "--treatment", "sum-rand", "--quiet"});
    REQUIRE(run.exit_code == 0);

    // shape (a replay of the stored best with the run's own arena) gives the r_max evolve stored
    const auto shaped = run_cli({"shape", "--kb", p("kb.db"), "--run", p("run.db"), "--json"});
    REQUIRE(shaped.exit_code == 0);
    const auto answer = nlohmann::json::parse(shaped.out);
    db::Connection connection(dir / "run.db", db::OpenMode::read_only);
    auto query = connection.prepare("SELECT r_max FROM individual WHERE id = ?1");
    query.bind(1, answer["individual_id"].get<std::int64_t>());
    REQUIRE(query.step());
    CHECK(answer["r_max"].get<double>() == query.column_double(0));
    CHECK(answer["r_max"].get<double>() > 0.0);

    // render draws the run's arena: the pillar is wall, where the paper has its horizontal wall is floor
    REQUIRE(run_cli({"render", p("run.db"), "--out", p("best.png")}).exit_code == 0);
    const auto image = reporttest::decode_png(test::read_file(dir / "best.png"));
    const auto layout = report::ArenaLayout::fit(sim::ArenaSpec::load(kArenas / "two_rooms.json"));
    const auto at = [&](double x, double y) {
        return image.at(static_cast<int>(std::floor(layout.px(x))),
                        static_cast<int>(std::floor(layout.py(y))));
    };
    CHECK(at(450, 130) == rgb(report::kWall));   // inside the pillar, clear of the path drawn
    CHECK(at(250, 203) == rgb(report::kFloor));  // the paper's horizontal wall, x 201.7-453
    CHECK(at(300, 100) == rgb(report::kWall));   // the divider above the door
}

TEST_CASE("a broken arena is refused with one line before any file is written",
          "[report][arena][cli][errors]") {
    const TempDir dir;
    auto arena = nlohmann::json::parse(test::read_file(kArenas / "two_rooms.json"));
    arena["starts"][0] = {440, 205, 0};
    test::write_file(dir / "bad.json", arena.dump());
    test::write_file(dir / "run.json",
                     R"({"task": {"kind": "target", "arena": "bad.json", "steps_per_start": 100}})");
    const auto run =
        run_cli({"evolve", "--config", (dir / "run.json").string(), "--db", (dir / "run.db").string()});
    CHECK(run.exit_code == 2);
    CHECK_THAT(run.err, Contains("bad.json: starts[0]: (440, 205) puts the robot inside the wall 'pillar'"));
    CHECK(std::count(run.err.begin(), run.err.end(), '\n') == 1);
    CHECK_FALSE(std::filesystem::exists(dir / "run.db"));

    const auto check = run_cli({"arena", (dir / "bad.json").string()});
    CHECK(check.exit_code == 2);
    CHECK_THAT(check.err, Contains("starts[0]"));
    test::write_file(dir / "missing.json", R"({"task": {"arena": "nowhere.json"}})");
    const auto missing =
        run_cli({"evolve", "--config", (dir / "missing.json").string(), "--db", (dir / "m.db").string()});
    CHECK(missing.exit_code == 2);
    CHECK_THAT(missing.err, Contains("nowhere.json"));

    // the scripted controller knows the paper's arena only
    const auto scripted = run_cli(
        {"simulate", "--arena", (kArenas / "two_rooms.json").string(), "--csv", (dir / "s.csv").string()});
    CHECK(scripted.exit_code == 2);
    CHECK_THAT(scripted.err, Contains("--controller random"));
    CHECK(run_cli({"simulate", "--arena", (kArenas / "two_rooms.json").string(), "--controller", "random",
                   "--steps", "50", "--starts", "1", "--csv", (dir / "r.csv").string()})
              .exit_code == 0);
    // `arena --json` of the shipped files is the files themselves
    CHECK(run_cli({"arena", "--json"}).out == test::read_file(kArenas / "paper.json"));
    CHECK(run_cli({"arena", (kArenas / "two_rooms.json").string(), "--json"}).out ==
          test::read_file(kArenas / "two_rooms.json"));
}
