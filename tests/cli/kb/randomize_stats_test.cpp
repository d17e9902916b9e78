#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "db/database.hpp"
#include "db/kb_store.hpp"
#include "support/kb_fixtures.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;

TEST_CASE("kb randomize keeps the segments, draws averages below 1 reproducibly and records the seed",
          "[cli][kb][randomize]") {
    test::TempDir dir;
    kbtest::make_run(dir / "run.db");
    const auto run = (dir / "run.db").string();
    REQUIRE(test::run_cli({"kb", "export", run, "--out", (dir / "kb.db").string()}).exit_code == 0);
    const auto kb_file = (dir / "kb.db").string();
    REQUIRE(test::run_cli({"kb", "randomize", kb_file, "--out", (dir / "r1.db").string(), "--seed", "7"})
                .exit_code == 0);
    REQUIRE(test::run_cli({"kb", "randomize", kb_file, "--out", (dir / "r2.db").string(), "--seed", "7"})
                .exit_code == 0);
    REQUIRE(test::run_cli({"kb", "randomize", kb_file, "--out", (dir / "r8.db").string(), "--seed", "8"})
                .exit_code == 0);

    const auto original = kbtest::load_kb(dir / "kb.db");
    auto connection = db::open_database(dir / "r1.db", db::OpenMode::read_only);
    const auto randomized = db::load_kb(connection);
    CHECK(randomized.name == "run-rand");
    REQUIRE(randomized.randomized_seed);
    CHECK(*randomized.randomized_seed == 7);
    CHECK(connection.query_int("SELECT randomized_seed FROM kb") == 7);
    REQUIRE(randomized.kb.size() == original.size());
    CHECK(std::equal(original.values().begin(), original.values().end(), randomized.kb.values().begin()));
    bool some_differ = false;
    for (std::size_t i = 0; i < original.size(); ++i) {
        const auto& record = randomized.kb.record(i);
        CHECK(record.count == 1);
        CHECK(record.average() >= 0.0);
        CHECK(record.average() < 1.0);
        CHECK(record.first.generation == original.record(i).first.generation);  // provenance kept
        some_differ = some_differ || record.average() != original.record(i).average();
    }
    CHECK(some_differ);  // the run's rewards are all 0; U[0, 1) draws are not
    CHECK(randomized.kb.sources()[0].run == original.sources()[0].run);
    // the same seed gives the same file content, another seed other averages
    CHECK(kbtest::segment_rows(dir / "r1.db") == kbtest::segment_rows(dir / "r2.db"));
    CHECK(kbtest::segment_rows(dir / "r1.db") != kbtest::segment_rows(dir / "r8.db"));
}

TEST_CASE("kb stats reports size, histogram, counts and provenance of a hand-made KB", "[cli][kb][stats]") {
    test::TempDir dir;
    kbtest::write_kb(dir / "h.db", "hand", kbtest::histogram_kb(), 11);
    auto result = test::run_cli({"kb", "stats", (dir / "h.db").string(), "--json"});
    REQUIRE(result.exit_code == 0);
    const auto stats = nlohmann::json::parse(result.out);
    CHECK(stats["name"] == "hand");
    CHECK(stats["segments"] == 8);
    CHECK(stats["segment_width"] == 1);
    CHECK(stats["channels"] == 1);
    CHECK(stats["delta"] == 0.5);
    CHECK(stats["randomized_seed"] == 11);
    CHECK(stats["max_average_reward"] == 1.0);
    // by hand: bins of 0.1 over [0, 1]: 0, 0, 0 -> bin 0; 0.15 -> 1; 0.55, 0.55 -> 5;
    // 0.95 -> 9 and the maximum 1.0 closes the last bin
    const std::vector<int> expected{3, 1, 0, 0, 0, 2, 0, 0, 0, 2};
    REQUIRE(stats["histogram"].size() == 10);
    for (std::size_t b = 0; b < 10; ++b) {
        INFO("bin " << b);
        CHECK(stats["histogram"][b]["segments"] == expected[b]);
        CHECK(stats["histogram"][b]["low"].get<double>() == Approx(0.1 * static_cast<double>(b)));
    }
    // counts 1 2 3 1 4 1 1 2: 15 observations, sorted 1 1 1 1 2 2 3 4
    CHECK(stats["counts"]["observations"] == 15);
    CHECK(stats["counts"]["min"] == 1);
    CHECK(stats["counts"]["max"] == 4);
    CHECK(stats["counts"]["median"] == 1.5);
    CHECK(stats["counts"]["mean"] == 1.875);
    CHECK(stats["counts"]["seen_once"] == 4);
    REQUIRE(stats["sources"].size() == 2);
    CHECK(stats["sources"][0]["run"] == "alpha");
    CHECK(stats["sources"][0]["policies"] == 30);
    CHECK(stats["sources"][1]["first_generation"] == 5);
    CHECK(stats["sources"][1]["last_generation"] == 7);
    CHECK(stats["bytes_per_segment"]["memory"].get<double>() > 4.0);  // at least the one float value
    CHECK(stats["bytes_per_segment"]["file"].get<double>() > 0.0);

    // the text form: the first bin's bar is the longest (50 #), the second a third of it
    result = test::run_cli({"kb", "stats", (dir / "h.db").string()});
    REQUIRE(result.exit_code == 0);
    CHECK_THAT(result.out, Contains("segments        8"));
    // (bars are ceil(50 x segments / 3): 50, 17, 34)
    const std::string gap(13, ' ');
    CHECK_THAT(result.out, Contains("[0.0000, 0.1000)" + gap + "3  " + std::string(50, '#') + "\n"));
    CHECK_THAT(result.out, Contains("[0.1000, 0.2000)" + gap + "1  " + std::string(17, '#') + "\n"));
    CHECK_THAT(result.out, Contains("[0.2000, 0.3000)" + gap + "0  \n"));
    CHECK_THAT(result.out, Contains("[0.9000, 1.0000]" + gap + "2  " + std::string(34, '#') + "\n"));
    CHECK_THAT(result.out, Contains("alpha: generations 0 to 10, 30 policies"));
    CHECK_THAT(result.out, Contains("randomized_seed 11"));
}

TEST_CASE("a KB exported from a source run takes at most 800 bytes a segment in its file",
          "[cli][kb][stats]") {
    // the paper's channels (15, 9 of them binary) and width (20); 1 start of 400 steps, 16 policies
    // a generation for 12 generations: some 900 segments, so that the file's fixed pages weigh little
    test::TempDir dir;
    test::write_file(dir / "source.json",
                     R"({"task": {"kind": "source", "steps_per_start": 400, "starts": 1},
                         "ea": {"population_size": 16, "generations": 12},
                         "kb": {"segment_width": 20, "delta": 1.83, "period": 1}})");
    REQUIRE(test::run_cli({"evolve", "--config", (dir / "source.json").string(), "--db",
                           (dir / "run.db").string(), "--seed", "1", "--quiet"})
                .exit_code == 0);
    REQUIRE(test::run_cli({"kb", "export", (dir / "run.db").string(), "--out", (dir / "kb.db").string()})
                .exit_code == 0);
    const auto stats = test::run_cli({"kb", "stats", (dir / "kb.db").string(), "--json"});
    REQUIRE(stats.exit_code == 0);
    const auto json = nlohmann::json::parse(stats.out);
    CAPTURE(json["segments"], json["bytes_per_segment"]);
    REQUIRE(json["segments"].get<int>() > 500);
    // raw float32 alone would be 1,200 bytes a segment
    CHECK(json["bytes_per_segment"]["file"].get<double>() <= 800.0);
}
