#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "db/database.hpp"
#include "db/kb_store.hpp"
#include "evo/pareto.hpp"
#include "runs/replay.hpp"
#include "sim/sensors.hpp"
#include "support/kb_fixtures.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;

namespace {

constexpr auto kChannels = static_cast<std::size_t>(sim::kChannels);

// the oracle: the KB's own lookup on the replayed behaviour
kb::Lookup expected_lookup(const kb::KnowledgeBase& kb, const std::filesystem::path& run, std::int64_t id) {
    const auto behaviour = runs::replay_behaviour(run, std::to_string(id));
    return kb.lookup(kb::segment_behaviour(behaviour, kChannels, kb.params().segment_width));
}

struct Row {
    std::int64_t individual = 0;
    std::int64_t segment = 0;
    std::optional<std::int64_t> kb_segment;
    double distance = 0;
    double average = 0;
};

std::vector<Row> policy_rows(const std::filesystem::path& run, std::int64_t kb_id) {
    auto connection = db::open_database(run, db::OpenMode::read_only);
    auto select = connection.prepare(
        "SELECT individual_id, segment, kb_segment_id, distance, average_reward FROM policy_segment "
        "WHERE kb_id = ?1 ORDER BY individual_id, segment");
    select.bind(1, kb_id);
    std::vector<Row> rows;
    while (select.step()) {
        Row row{select.column_int(0), select.column_int(1), std::nullopt, select.column_double(3),
                select.column_double(4)};
        if (!select.is_null(2)) row.kb_segment = select.column_int(2);
        rows.push_back(row);
    }
    return rows;
}

void check_rows(const std::vector<Row>& rows, std::size_t& at, std::int64_t id, const kb::Lookup& lookup) {
    for (std::size_t s = 0; s < lookup.segments.size(); ++s, ++at) {
        REQUIRE(at < rows.size());
        const auto& row = rows[at];
        const auto& match = lookup.segments[s];
        CHECK(row.individual == id);
        CHECK(row.segment == static_cast<std::int64_t>(s));
        CHECK(row.kb_segment.has_value() == match.id.has_value());
        if (match.id) CHECK(*row.kb_segment == static_cast<std::int64_t>(*match.id));
        CHECK(row.distance == match.distance);
        CHECK(row.average == match.average_reward);
    }
}

}  // namespace

TEST_CASE("kb annotate all fills policy_segment as KnowledgeBase::lookup on the replayed behaviours",
          "[cli][kb][annotate]") {
    test::TempDir dir;
    kbtest::make_run(dir / "run.db", /*retain_all=*/true);
    const auto run = dir / "run.db";
    REQUIRE(test::run_cli({"kb", "export", run.string(), "--out", (dir / "kb.db").string()}).exit_code == 0);
    REQUIRE(test::run_cli({"kb", "randomize", (dir / "kb.db").string(), "--out", (dir / "rand.db").string(),
                           "--seed", "2"})
                .exit_code == 0);

    // the exported KB is the run's own: it is reused, not copied
    auto result = test::run_cli(
        {"kb", "annotate", run.string(), "--kb", (dir / "kb.db").string(), "--individuals", "all"});
    REQUIRE(result.exit_code == 0);
    CHECK_THAT(result.out, Contains("already in the run file"));
    // the randomized KB is copied into the run file under its own name
    result = test::run_cli(
        {"kb", "annotate", run.string(), "--kb", (dir / "rand.db").string(), "--individuals", "all"});
    REQUIRE(result.exit_code == 0);
    CHECK_THAT(result.out, Contains("copied into the run file"));

    std::vector<std::int64_t> ids;
    std::int64_t run_kb = 0, rand_kb = 0;
    {
        auto connection = db::open_database(run, db::OpenMode::read_only);
        auto select = connection.prepare("SELECT individual_id FROM genome ORDER BY individual_id");
        while (select.step()) ids.push_back(select.column_int(0));
        for (const auto& summary : db::list_kbs(connection)) {
            if (summary.name == "run") run_kb = summary.id;
            if (summary.name == "run-rand") rand_kb = summary.id;
        }
        CHECK(db::list_kbs(connection).size() == 2);
    }
    REQUIRE(ids.size() == 40);  // --retain all: 16 random at generation 0, then 8 per generation
    REQUIRE(run_kb != 0);
    REQUIRE(rand_kb != 0);

    for (const auto& [file, kb_id] :
         {std::pair{dir / "kb.db", run_kb}, std::pair{dir / "rand.db", rand_kb}}) {
        const auto kb = kbtest::load_kb(file);
        const auto rows = policy_rows(run, kb_id);
        CHECK(rows.size() == ids.size() * (kbtest::kRunSteps / kbtest::kRunWidth));
        std::size_t at = 0;
        for (std::int64_t id : ids) check_rows(rows, at, id, expected_lookup(kb, run, id));
    }

    // annotating again replaces the rows instead of adding to them
    REQUIRE(test::run_cli(
                {"kb", "annotate", run.string(), "--kb", (dir / "kb.db").string(), "--individuals", "all"})
                .exit_code == 0);
    CHECK(policy_rows(run, run_kb).size() == ids.size() * (kbtest::kRunSteps / kbtest::kRunWidth));
}

TEST_CASE("kb annotate front takes the first front of the last population, best the best stored genome",
          "[cli][kb][annotate]") {
    test::TempDir dir;
    kbtest::make_run(dir / "run.db");
    const auto run = dir / "run.db";
    REQUIRE(test::run_cli({"kb", "export", run.string(), "--out", (dir / "kb.db").string()}).exit_code == 0);

    // oracle for front: members of the checkpoint population that no other member dominates
    std::vector<std::int64_t> front;
    std::int64_t best = 0;
    {
        auto connection = db::open_database(run, db::OpenMode::read_only);
        auto select = connection.prepare("SELECT state FROM checkpoint");
        REQUIRE(select.step());
        const auto state = nlohmann::json::parse(select.column_text(0));
        const auto& population = state.at("population");
        for (const auto& a : population) {
            const auto oa = a.at("objectives").get<std::vector<double>>();
            bool dominated = false;
            for (const auto& b : population) {
                const auto ob = b.at("objectives").get<std::vector<double>>();
                dominated = dominated || evo::dominates(ob, oa);
            }
            if (!dominated) front.push_back(a.at("id").get<std::int64_t>());
        }
        std::sort(front.begin(), front.end());
        auto top = connection.prepare(
            "SELECT g.individual_id FROM genome g JOIN individual i ON i.id = g.individual_id "
            "ORDER BY i.reward DESC, i.id LIMIT 1");
        REQUIRE(top.step());
        best = top.column_int(0);
    }
    REQUIRE(!front.empty());

    REQUIRE(test::run_cli(
                {"kb", "annotate", run.string(), "--kb", (dir / "kb.db").string(), "--individuals", "front"})
                .exit_code == 0);
    auto connection = db::open_database(run, db::OpenMode::read_only);
    auto select = connection.prepare("SELECT DISTINCT individual_id FROM policy_segment ORDER BY 1");
    std::vector<std::int64_t> annotated;
    while (select.step()) annotated.push_back(select.column_int(0));
    CHECK(annotated == front);

    REQUIRE(test::run_cli({"kb", "annotate", run.string(), "--kb", (dir / "kb.db").string()}).exit_code == 0);
    CHECK(
        connection.query_int(
            ("SELECT count(*) FROM policy_segment WHERE individual_id = " + std::to_string(best)).c_str()) ==
        static_cast<std::int64_t>(kbtest::kRunSteps / kbtest::kRunWidth));
}

TEST_CASE("shape prints the r_max and matches that KnowledgeBase::lookup gives for the stored policy",
          "[cli][kb][shape]") {
    test::TempDir dir;
    kbtest::make_run(dir / "run.db");
    const auto run = dir / "run.db";
    REQUIRE(test::run_cli({"kb", "export", run.string(), "--out", (dir / "kb.db").string()}).exit_code == 0);
    REQUIRE(test::run_cli({"kb", "randomize", (dir / "kb.db").string(), "--out", (dir / "rand.db").string(),
                           "--seed", "5"})
                .exit_code == 0);
    // the randomized KB gives non-zero averages, so r_max is a real maximum
    for (const char* name : {"kb.db", "rand.db"}) {
        INFO(name);
        auto result = test::run_cli({"shape", "--kb", (dir / name).string(), "--run", run.string(),
                                     "--individual", "best", "--json"});
        REQUIRE(result.exit_code == 0);
        const auto out = nlohmann::json::parse(result.out);
        runs::Replay best;
        runs::replay_behaviour(run, "best", &best);
        const auto kb = kbtest::load_kb(dir / name);
        const auto lookup = expected_lookup(kb, run, best.individual_id);
        CHECK(out["individual_id"] == best.individual_id);
        CHECK(out["r_max"].get<double>() == lookup.r_max);
        CHECK(out["kb"]["segment_width"] == kbtest::kRunWidth);
        REQUIRE(out["segments"].size() == lookup.segments.size());
        for (std::size_t s = 0; s < lookup.segments.size(); ++s) {
            const auto& row = out["segments"][s];
            const auto& match = lookup.segments[s];
            CHECK(row["step_start"] == s * kbtest::kRunWidth);
            CHECK(row["step_end"] == (s + 1) * kbtest::kRunWidth);
            CHECK(row["kb_segment_id"].is_null() == !match.id.has_value());
            if (match.id) CHECK(row["kb_segment_id"] == *match.id);
            CHECK(row["distance"].get<double>() == match.distance);
            CHECK(row["average_reward"].get<double>() == match.average_reward);
        }
        // by an id too, with the text form
        result = test::run_cli({"shape", "--kb", (dir / name).string(), "--run", run.string(), "--individual",
                                std::to_string(best.individual_id)});
        REQUIRE(result.exit_code == 0);
        CHECK_THAT(result.out, Contains("individual " + std::to_string(best.individual_id)));
        CHECK_THAT(result.out, Contains("r_max "));
    }
}
