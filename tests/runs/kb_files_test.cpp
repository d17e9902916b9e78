// KB files in, one KB file out (lib/runs/kb_files.cpp): the names a written KB
// takes by default, an existing output refused unless forced, the KB chosen by
// name, a merge's size and counts by hand, and inputs that cannot be merged.
#include "runs/kb_files.hpp"

#include <catch2/catch.hpp>

#include "core/error.hpp"
#include "db/database.hpp"
#include "db/kb_store.hpp"
#include "support/kb_fixtures.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;

TEST_CASE("a KB file keeps its KB unless forced, and randomize and merge name their output as documented",
          "[runs][kb][files]") {
    test::TempDir dir;
    // policies {x, y, reward, generation}: two segments each, 5 apart (delta 0.5)
    const auto alpha = kbtest::point_kb("run-a", {{0, 0, 1, 0}, {5, 0, 0.5, 0}});
    const auto beta = kbtest::point_kb("run-b", {{0, 0, 0, 1}, {0, 5, 0.25, 1}});
    runs::save_kb_file(dir / "a.db", false, "alpha", alpha);
    runs::save_kb_file(dir / "b.db", false, "beta", beta);
    CHECK(runs::load_kb_file(dir / "a.db", "").name == "alpha");

    // an existing output: refused without force, the file as it was; replaced with it
    CHECK_THROWS_AS(runs::save_kb_file(dir / "a.db", false, "other", beta), ConfigError);
    CHECK(runs::load_kb_file(dir / "a.db", "alpha").kb.size() == 2);
    runs::save_kb_file(dir / "c.db", false, "gamma", beta);
    runs::save_kb_file(dir / "c.db", true, "delta", alpha);
    const auto replaced = runs::load_kb_file(dir / "c.db", "");
    CHECK(replaced.name == "delta");
    CHECK_THROWS_WITH(runs::load_kb_file(dir / "c.db", "gamma"), Contains("gamma"));

    // randomize: the input's name followed by -rand unless named, its seed recorded
    const auto randomized = runs::randomize_kb_file(dir / "a.db", dir / "r.db", 5, "", false);
    CHECK(randomized.name == "alpha-rand");
    CHECK(randomized.randomized_seed == std::optional<std::uint64_t>(5));
    CHECK(randomized.segments == 2);
    const auto stored = runs::load_kb_file(dir / "r.db", "alpha-rand");
    CHECK(stored.randomized_seed == std::optional<std::uint64_t>(5));
    CHECK(runs::randomize_kb_file(dir / "a.db", dir / "s.db", 5, "control", false).name == "control");

    // merge: the first KB's name unless named; (0, 0) is in both, so 3 segments and 4 observations
    const std::vector<std::filesystem::path> inputs{dir / "a.db", dir / "b.db"};
    const auto merged = runs::merge_kb_files(inputs, dir / "m.db", "", false);
    CHECK(merged.name == "alpha");
    CHECK(merged.segments == 3);
    const auto kb = runs::load_kb_file(dir / "m.db", "").kb;
    std::uint64_t observations = 0;
    for (const auto& record : kb.records()) observations += record.count;
    CHECK(observations == 4);
    CHECK(kb.record(0).count == 2);
    CHECK(kb.record(0).cum_reward == 1.0);  // 1 from alpha, 0 from beta
    CHECK(kb.sources().size() == 2);
    CHECK(runs::merge_kb_files(inputs, dir / "n.db", "union", false).name == "union");
}

TEST_CASE("a merge refuses one input, or KBs of another delta, naming both files and leaving no output",
          "[runs][kb][files][errors]") {
    test::TempDir dir;
    runs::save_kb_file(dir / "a.db", false, "a", kbtest::point_kb("run-a", {{0, 0, 1, 0}}));
    runs::save_kb_file(dir / "b.db", false, "b", kbtest::point_kb("run-b", {{1, 1, 1, 0}}, 1.0));
    const std::vector<std::filesystem::path> one{dir / "a.db"};
    CHECK_THROWS_WITH(runs::merge_kb_files(one, dir / "m.db", "", false),
                      "kb merge needs at least two KB files, got 1");
    const std::vector<std::filesystem::path> two{dir / "a.db", dir / "b.db"};
    CHECK_THROWS_WITH(runs::merge_kb_files(two, dir / "m.db", "", false),
                      "cannot merge " + (dir / "b.db").string() + " into " + (dir / "a.db").string() +
                          ": delta is 1 in " + (dir / "b.db").string() + ", 0.5 in " +
                          (dir / "a.db").string());
    CHECK_FALSE(std::filesystem::exists(dir / "m.db"));
}
