#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <limits>

#include "db/database.hpp"
#include "db/kb_store.hpp"
#include "support/kb_fixtures.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;

namespace {

// A: (0,0) seen with rewards 1 and 0.5, (3,3) with 0.25
std::vector<kbtest::Policy> policies_a() { return {{0, 0, 1.0, 0}, {0, 0, 0.5, 1}, {3, 3, 0.25, 2}}; }
// B: (0.1,0) seen with rewards 0.5 and 0.3, (5,5) with 1
std::vector<kbtest::Policy> policies_b() { return {{0.1f, 0, 0.5, 4}, {5, 5, 1.0, 5}, {0.1f, 0, 0.3, 6}}; }

// A KB coarsened as docs/knowledge_base.md says, by a plain loop: the segments
// observed in id order into an empty KB of the larger delta, each adding its
// cumulated reward and count to the nearest kept segment (lowest id on ties)
// when that lies closer than delta, else kept with its own record.
struct Coarsened {
    std::vector<std::vector<float>> segments;
    std::vector<double> cum_reward;
    std::vector<std::uint64_t> count;
};

Coarsened coarsen_by_hand(const kb::KnowledgeBase& fine, double delta) {
    Coarsened out;
    for (std::size_t i = 0; i < fine.size(); ++i) {
        const auto s = fine.segment(i);
        std::size_t nearest = 0;
        double nearest_distance = std::numeric_limits<double>::infinity();
        for (std::size_t k = 0; k < out.segments.size(); ++k) {
            double sum = 0.0;
            for (std::size_t v = 0; v < s.size(); ++v) {
                const double d = static_cast<double>(s[v]) - static_cast<double>(out.segments[k][v]);
                sum += d * d;
            }
            if (std::sqrt(sum) < nearest_distance) {
                nearest_distance = std::sqrt(sum);
                nearest = k;
            }
        }
        if (nearest_distance < delta) {
            out.cum_reward[nearest] += fine.record(i).cum_reward;
            out.count[nearest] += fine.record(i).count;
        } else {
            out.segments.emplace_back(s.begin(), s.end());
            out.cum_reward.push_back(fine.record(i).cum_reward);
            out.count.push_back(fine.record(i).count);
        }
    }
    return out;
}

}  // namespace

TEST_CASE("kb export writes the run's knowledge base unchanged under the same name", "[cli][kb][export]") {
    test::TempDir dir;
    kbtest::make_run(dir / "run.db");
    auto result =
        test::run_cli({"kb", "export", (dir / "run.db").string(), "--out", (dir / "kb.db").string()});
    REQUIRE(result.exit_code == 0);
    CHECK_THAT(result.out, Contains("knowledge base \"run\""));

    auto run = db::open_database(dir / "run.db", db::OpenMode::read_only);
    auto file = db::open_database(dir / "kb.db", db::OpenMode::read_only);
    const auto from_run = db::load_kb(run, "run");
    const auto exported = db::load_kb(file);
    CHECK(exported.name == "run");
    CHECK(db::list_kbs(file).size() == 1);
    CHECK(exported.kb.params().segment_width == kbtest::kRunWidth);  // the config's width
    CHECK(exported.kb.params().delta == 1.0);
    REQUIRE(exported.kb.size() == from_run.kb.size());
    REQUIRE(exported.kb.size() > 0);
    CHECK(std::equal(exported.kb.values().begin(), exported.kb.values().end(), from_run.kb.values().begin()));
    for (std::size_t i = 0; i < exported.kb.size(); ++i) {
        const auto& a = exported.kb.record(i);
        const auto& b = from_run.kb.record(i);
        CHECK(a.cum_reward == b.cum_reward);
        CHECK(a.count == b.count);
        CHECK(a.first.generation == b.first.generation);
        CHECK(a.last.generation == b.last.generation);
    }
    REQUIRE(exported.kb.sources().size() == 1);
    CHECK(exported.kb.sources()[0].run == from_run.kb.sources()[0].run);
    CHECK(exported.kb.sources()[0].last_generation == 3);  // generations 0 to 3, period 1
    CHECK(exported.kb.sources()[0].policies == from_run.kb.sources()[0].policies);

    // the names every kb command shares: --kb-name picks the input's KB, --name names the output
    result = test::run_cli({"kb", "export", (dir / "run.db").string(), "--kb-name", "run", "--name", "mine",
                            "--out", (dir / "named.db").string()});
    REQUIRE(result.exit_code == 0);
    auto named = db::open_database(dir / "named.db", db::OpenMode::read_only);
    CHECK(db::list_kbs(named).at(0).name == "mine");
    CHECK(db::load_kb(named).kb.size() == from_run.kb.size());
    result = test::run_cli({"kb", "stats", (dir / "named.db").string(), "--kb-name", "mine", "--json"});
    REQUIRE(result.exit_code == 0);
    CHECK_THAT(result.out, Contains("\"mine\""));
    result = test::run_cli({"kb", "stats", (dir / "named.db").string(), "--kb-name", "run"});
    CHECK(result.exit_code == 1);
}

TEST_CASE("kb merge adds counts and cumulated rewards of segments within delta and keeps provenance",
          "[cli][kb][merge]") {
    test::TempDir dir;
    kbtest::write_kb(dir / "a.db", "a", kbtest::point_kb("run-a", policies_a()));
    kbtest::write_kb(dir / "b.db", "b", kbtest::point_kb("run-b", policies_b()));
    auto result = test::run_cli(
        {"kb", "merge", (dir / "a.db").string(), (dir / "b.db").string(), "--out", (dir / "m.db").string()});
    REQUIRE(result.exit_code == 0);

    auto connection = db::open_database(dir / "m.db", db::OpenMode::read_only);
    const auto merged = db::load_kb(connection);
    CHECK(merged.name == "a");  // the first KB's name
    // by hand: B's (0.1,0) is 0.1 from A's (0,0) (< 0.5): cum 1.5 + 0.8, count 2 + 2;
    // B's (5,5) is 2.83 from (3,3): inserted after A's segments
    REQUIRE(merged.kb.size() == 3);
    CHECK(merged.kb.record(0).cum_reward == Approx(2.3));
    CHECK(merged.kb.record(0).count == 4);
    CHECK(merged.kb.record(1).cum_reward == 0.25);
    CHECK(merged.kb.record(1).count == 1);
    CHECK(merged.kb.record(2).cum_reward == 1.0);
    CHECK(merged.kb.record(2).count == 1);
    CHECK(merged.kb.segment(2)[0] == 5.0f);
    // provenance: both runs, generations and policies as observed
    REQUIRE(merged.kb.sources().size() == 2);
    CHECK(merged.kb.sources()[0].run == "run-a");
    CHECK(merged.kb.sources()[0].policies == 3);
    CHECK(merged.kb.sources()[1].run == "run-b");
    CHECK(merged.kb.sources()[1].first_generation == 4);
    CHECK(merged.kb.sources()[1].last_generation == 6);
    CHECK(merged.kb.record(2).first.source == 1);  // inserted from run-b
    CHECK(merged.kb.record(0).last.source == 1);   // last credited by run-b

    // --name renames the output
    result = test::run_cli({"kb", "merge", (dir / "a.db").string(), (dir / "b.db").string(), "--out",
                            (dir / "n.db").string(), "--name", "both"});
    REQUIRE(result.exit_code == 0);
    auto named = db::open_database(dir / "n.db", db::OpenMode::read_only);
    CHECK(db::list_kbs(named).at(0).name == "both");
}

TEST_CASE("kb merge is deterministic in the given order", "[cli][kb][merge][determinism]") {
    test::TempDir dir;
    kbtest::write_kb(dir / "a.db", "a", kbtest::point_kb("run-a", policies_a()));
    kbtest::write_kb(dir / "b.db", "b", kbtest::point_kb("run-b", policies_b()));
    const auto a = (dir / "a.db").string();
    const auto b = (dir / "b.db").string();
    REQUIRE(test::run_cli({"kb", "merge", a, b, "--out", (dir / "ab1.db").string()}).exit_code == 0);
    REQUIRE(test::run_cli({"kb", "merge", a, b, "--out", (dir / "ab2.db").string()}).exit_code == 0);
    REQUIRE(test::run_cli({"kb", "merge", b, a, "--out", (dir / "ba.db").string()}).exit_code == 0);
    CHECK(kbtest::segment_rows(dir / "ab1.db") == kbtest::segment_rows(dir / "ab2.db"));

    // B first: B's (0.1,0) keeps id 0 and absorbs A's (0,0); A's (3,3) comes last
    const auto ba = kbtest::load_kb(dir / "ba.db");
    REQUIRE(ba.size() == 3);
    CHECK(ba.segment(0)[0] == 0.1f);
    CHECK(ba.record(0).cum_reward == Approx(2.3));
    CHECK(ba.record(0).count == 4);
    CHECK(ba.segment(1)[0] == 5.0f);
    CHECK(ba.segment(2)[0] == 3.0f);
    CHECK(ba.sources()[0].run == "run-b");
    CHECK(kbtest::segment_rows(dir / "ba.db") != kbtest::segment_rows(dir / "ab1.db"));
}

TEST_CASE("kb merge refuses KBs of another delta or channel count, naming both files, and writes nothing",
          "[cli][kb][merge][errors]") {
    test::TempDir dir;
    kbtest::write_kb(dir / "a.db", "a", kbtest::point_kb("run-a", policies_a()));
    kbtest::write_kb(dir / "wide.db", "w", kbtest::point_kb("run-w", policies_b(), 0.7));
    kbtest::write_kb(dir / "three.db", "t", kbtest::point_kb("run-t", policies_b(), 0.5, 3));
    const auto before = kbtest::files_in(dir.path());

    auto result = test::run_cli({"kb", "merge", (dir / "a.db").string(), (dir / "wide.db").string(), "--out",
                                 (dir / "m.db").string()});
    CHECK(result.exit_code == 1);
    REQUIRE(result.err_lines().size() == 1);
    CHECK_THAT(result.err,
               Contains("a.db") && Contains("wide.db") && Contains("delta is 0.7") && Contains("0.5"));

    result = test::run_cli({"kb", "merge", (dir / "a.db").string(), (dir / "a.db").string(),
                            (dir / "three.db").string(), "--out", (dir / "m.db").string()});
    CHECK(result.exit_code == 1);
    REQUIRE(result.err_lines().size() == 1);
    CHECK_THAT(result.err, Contains("three.db") && Contains("channels is 3") &&
                               Contains("2 in " + (dir / "a.db").string()));
    CHECK(kbtest::files_in(dir.path()) == before);  // no output, no temporary file
}

TEST_CASE("kb export --delta writes the run's KB coarsened under the larger delta",
          "[cli][kb][export][coarsen]") {
    test::TempDir dir;
    kbtest::make_run(dir / "run.db");
    {
        // the tiny run scores nothing, so every cum_reward is 0: the segments get rewards that
        // differ (0 to 1.25 a policy), so that a coarsening that mixes them up is seen
        auto connection = db::open_database(dir / "run.db", db::OpenMode::read_write);
        connection.exec("UPDATE kb_segment SET cum_reward = count * ((id * 37) % 11) / 8.0");
    }
    auto result = test::run_cli(
        {"kb", "export", (dir / "run.db").string(), "--out", (dir / "coarse.db").string(), "--delta", "3"});
    REQUIRE(result.exit_code == 0);
    CHECK_THAT(result.out, Contains("delta 3"));
    auto run = db::open_database(dir / "run.db", db::OpenMode::read_only);
    auto file = db::open_database(dir / "coarse.db", db::OpenMode::read_only);
    const auto from_run = db::load_kb(run, "run");
    const auto coarse = db::load_kb(file);
    // the expectation: the run's stored segments coarsened by the loop above, not by the library
    const auto expected = coarsen_by_hand(from_run.kb, 3.0);
    REQUIRE(from_run.kb.max_average() == 1.25);
    CHECK(coarse.kb.params().delta == 3.0);
    REQUIRE(coarse.kb.size() == expected.segments.size());
    CHECK(coarse.kb.size() < from_run.kb.size());  // some segments were absorbed by others
    for (std::size_t i = 0; i < coarse.kb.size(); ++i) {
        CAPTURE(i);
        const auto segment = coarse.kb.segment(i);
        CHECK(std::vector<float>(segment.begin(), segment.end()) == expected.segments[i]);
        CHECK(coarse.kb.record(i).cum_reward == Approx(expected.cum_reward[i]).epsilon(1e-12));
        CHECK(coarse.kb.record(i).count == expected.count[i]);
    }
    std::uint64_t count = 0, run_count = 0;
    for (std::size_t i = 0; i < coarse.kb.size(); ++i) count += coarse.kb.record(i).count;
    for (std::size_t i = 0; i < from_run.kb.size(); ++i) run_count += from_run.kb.record(i).count;
    CHECK(count == run_count);  // observations are moved, never lost

    // a delta below the run's (1.0) is a usage error and writes nothing
    const auto before = kbtest::files_in(dir.path());
    result = test::run_cli(
        {"kb", "export", (dir / "run.db").string(), "--out", (dir / "fine.db").string(), "--delta", "0.5"});
    CHECK(result.exit_code == 2);
    REQUIRE(result.err_lines().size() == 1);
    CHECK_THAT(result.err, Contains("at least the KB's 1"));
    CHECK(kbtest::files_in(dir.path()) == before);
}
