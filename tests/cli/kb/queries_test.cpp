#include <catch2/catch.hpp>
#include <fstream>
#include <map>
#include <sstream>
#include <variant>

#include "db/database.hpp"
#include "db/kb_store.hpp"
#include "runs/replay.hpp"
#include "sim/sensors.hpp"
#include "support/kb_fixtures.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;

namespace {

struct Cell {
    bool null = false;
    double number = 0;
    std::string text;
};
using Rows = std::vector<std::vector<Cell>>;
using Params = std::map<std::string, std::variant<std::int64_t, std::string>>;

// the text users run: the file of queries/ as shipped
std::string query_text(const std::string& name) {
    return test::read_file(std::filesystem::path(STEPSTONE_SOURCE_DIR) / "queries" / name);
}

Rows run_query(db::Connection& connection, const std::string& sql, const Params& params) {
    auto statement = connection.prepare(sql);
    for (const auto& [name, value] : params) {
        const int index = statement.parameter(":" + name);
        if (const auto* number = std::get_if<std::int64_t>(&value)) {
            statement.bind(index, *number);
        } else {
            statement.bind(index, std::get<std::string>(value));
        }
    }
    Rows rows;
    while (statement.step()) {
        std::vector<Cell> row;
        for (int c = 0; c < statement.column_count(); ++c) {
            Cell cell;
            cell.null = statement.is_null(c);
            if (!cell.null) {
                cell.number = statement.column_double(c);
                cell.text = statement.column_text(c);
            }
            row.push_back(cell);
        }
        rows.push_back(row);
    }
    return rows;
}

Rows run_file(db::Connection& connection, const std::string& name, const Params& params) {
    return run_query(connection, query_text(name), params);
}

// an annotated tiny run: the run's KB and its randomized copy (non-zero averages)
struct AnnotatedRun {
    test::TempDir dir;
    std::filesystem::path run = dir / "run.db";
    kb::KnowledgeBase random_kb{kb::KbParams{}};
    std::int64_t best = 0;
    AnnotatedRun() {
        kbtest::make_run(run);
        const auto kb_file = (dir / "kb.db").string();
        const auto rand_file = (dir / "rand.db").string();
        if (test::run_cli({"kb", "export", run.string(), "--out", kb_file}).exit_code != 0 ||
            test::run_cli({"kb", "randomize", kb_file, "--out", rand_file, "--seed", "9"}).exit_code != 0 ||
            test::run_cli({"kb", "annotate", run.string(), "--kb", rand_file}).exit_code != 0) {
            throw std::runtime_error("cannot build the annotated run");
        }
        random_kb = kbtest::load_kb(rand_file);
        runs::Replay replayed;
        runs::replay_behaviour(run, "best", &replayed);
        best = replayed.individual_id;
    }
    kb::Lookup lookup() const {
        const auto behaviour = runs::replay_behaviour(run, std::to_string(best));
        return random_kb.lookup(
            kb::segment_behaviour(behaviour, static_cast<std::size_t>(sim::kChannels), kbtest::kRunWidth));
    }
};

}  // namespace

TEST_CASE("salient_segments.sql lists the highest averages among segments seen often enough",
          "[cli][kb][queries]") {
    test::TempDir dir;
    kbtest::write_kb(dir / "h.db", "hand", kbtest::histogram_kb());
    auto connection = db::open_database(dir / "h.db", db::OpenMode::read_only);
    const auto rows = run_file(
        connection, "salient_segments.sql",
        {{"kb_name", std::string("hand")}, {"min_count", std::int64_t{2}}, {"limit", std::int64_t{3}}});
    // by hand, counts >= 2: id 1 (0, 2), id 2 (0, 3), id 4 (0.55, 4), id 7 (1.0, 2);
    // best first: 7, 4, then among the zeros the higher count: 2
    REQUIRE(rows.size() == 3);
    CHECK(rows[0][0].number == 7);
    CHECK(rows[0][1].number == 1.0);
    CHECK(rows[0][2].number == 2);
    CHECK(rows[0][4].text == "beta");
    CHECK(rows[0][5].number == 5);
    CHECK(rows[1][0].number == 4);
    CHECK(rows[1][1].number == Approx(0.55));
    CHECK(rows[1][4].text == "alpha");
    CHECK(rows[2][0].number == 2);
    CHECK(rows[2][2].number == 3);
    // with min_count 1 the maximum still comes first, and every segment is there
    CHECK(
        run_file(
            connection, "salient_segments.sql",
            {{"kb_name", std::string("hand")}, {"min_count", std::int64_t{1}}, {"limit", std::int64_t{100}}})
            .size() == 8);
}

TEST_CASE("kb_growth.sql counts the segments each generation inserted and the running size",
          "[cli][kb][queries]") {
    test::TempDir dir;
    kbtest::write_kb(dir / "h.db", "hand", kbtest::histogram_kb());
    auto connection = db::open_database(dir / "h.db", db::OpenMode::read_only);
    const auto rows = run_file(connection, "kb_growth.sql", {{"kb_name", std::string("hand")}});
    // first origins by construction: 3 at alpha 0, 3 at alpha 3, 2 at beta 5
    REQUIRE(rows.size() == 3);
    CHECK(rows[0][0].text == "alpha");
    CHECK(rows[0][1].number == 0);
    CHECK(rows[0][2].number == 3);
    CHECK(rows[0][3].number == 3);
    CHECK(rows[1][1].number == 3);
    CHECK(rows[1][3].number == 6);
    CHECK(rows[2][0].text == "beta");
    CHECK(rows[2][1].number == 5);
    CHECK(rows[2][2].number == 2);
    CHECK(rows[2][3].number == 8);

    // on a run's KB the last running size is the KB's size
    AnnotatedRun annotated;
    auto run = db::open_database(annotated.run, db::OpenMode::read_only);
    const auto growth = run_file(run, "kb_growth.sql", {{"kb_name", std::string("run")}});
    REQUIRE(!growth.empty());
    CHECK(growth.back()[3].number == static_cast<double>(kbtest::load_kb(annotated.run, "run").size()));
    CHECK(growth.front()[1].number == 0);  // generation 0 inserts first
}

TEST_CASE("kb_provenance.sql lists each source with the segments it inserted and last credited",
          "[cli][kb][queries]") {
    test::TempDir dir;
    kbtest::write_kb(dir / "h.db", "hand", kbtest::histogram_kb(), 11);
    auto connection = db::open_database(dir / "h.db", db::OpenMode::read_only);
    const auto rows = run_file(connection, "kb_provenance.sql", {{"kb_name", std::string("hand")}});
    REQUIRE(rows.size() == 2);
    // alpha inserted ids 0-5 and was last to credit 1-5; beta inserted 6-7 and last credited 0, 6, 7
    CHECK(rows[0][1].text == "alpha");
    CHECK(rows[0][2].number == 0);
    CHECK(rows[0][3].number == 10);
    CHECK(rows[0][4].number == 30);
    CHECK(rows[0][5].number == 6);
    CHECK(rows[0][6].number == 5);
    CHECK(rows[1][1].text == "beta");
    CHECK(rows[1][5].number == 2);
    CHECK(rows[1][6].number == 3);
    CHECK(rows[1][7].number == 11);  // randomized_seed
}

TEST_CASE("policy_saliency.sql and salient_positions.sql give the annotated policy's saliency along time",
          "[cli][kb][queries]") {
    AnnotatedRun annotated;
    const auto lookup = annotated.lookup();
    auto connection = db::open_database(annotated.run, db::OpenMode::read_only);
    const auto rows = run_file(connection, "policy_saliency.sql",
                               {{"kb_name", std::string("run-rand")}, {"individual_id", annotated.best}});
    REQUIRE(rows.size() == lookup.segments.size());
    for (std::size_t s = 0; s < rows.size(); ++s) {
        CHECK(rows[s][0].number == static_cast<double>(s));
        CHECK(rows[s][1].number == static_cast<double>(s * kbtest::kRunWidth));
        CHECK(rows[s][2].number == static_cast<double>((s + 1) * kbtest::kRunWidth));
        CHECK(rows[s][3].null == !lookup.segments[s].id.has_value());
        CHECK(rows[s][5].number == lookup.segments[s].average_reward);
    }

    // windows of 50 steps hold 5 segments of 10: their mean and maximum by hand
    const auto windows = run_file(connection, "salient_positions.sql",
                                  {{"kb_name", std::string("run-rand")},
                                   {"individual_id", annotated.best},
                                   {"window", std::int64_t{50}}});
    REQUIRE(windows.size() == kbtest::kRunSteps / 50);
    for (std::size_t w = 0; w < windows.size(); ++w) {
        double sum = 0, top = 0;
        for (std::size_t s = 5 * w; s < 5 * w + 5; ++s) {
            sum += lookup.segments[s].average_reward;
            top = std::max(top, lookup.segments[s].average_reward);
        }
        CHECK(windows[w][0].number == static_cast<double>(w));
        CHECK(windows[w][1].number == static_cast<double>(50 * w));
        CHECK(windows[w][2].number == static_cast<double>(50 * w + 50));
        CHECK(windows[w][3].number == 5);
        CHECK(windows[w][4].number == Approx(sum / 5));
        CHECK(windows[w][5].number == top);
    }
}

TEST_CASE("salient_positions.sql joins with the replay CSV as its header describes", "[cli][kb][queries]") {
    AnnotatedRun annotated;
    const auto csv = annotated.dir / "steps.csv";
    REQUIRE(test::run_cli({"replay", annotated.run.string(), "--individual", std::to_string(annotated.best),
                           "--csv", csv.string()})
                .exit_code == 0);
    // the CSV's start, step, x, y; the mean x per 50-step window of start 1 (the first), by hand
    std::ifstream in(csv);
    std::string line;
    std::getline(in, line);
    REQUIRE(line.rfind("start,step,x,y,", 0) == 0);
    std::map<std::int64_t, std::pair<double, int>> mean_x;
    std::vector<std::tuple<std::int64_t, std::int64_t, double, double>> steps;
    while (std::getline(in, line)) {
        std::istringstream fields(line);
        std::string start, step, x, y;
        std::getline(fields, start, ',');
        std::getline(fields, step, ',');
        std::getline(fields, x, ',');
        std::getline(fields, y, ',');
        steps.emplace_back(std::stoll(start), std::stoll(step), std::stod(x), std::stod(y));
        if (std::stoll(start) == 1) {
            auto& [sum, n] = mean_x[std::stoll(step) / 50];
            sum += std::stod(x);
            ++n;
        }
    }
    REQUIRE(!mean_x.empty());

    // a temporary table as `.import --csv --schema temp` makes; the run file is not changed
    auto connection = db::open_database(annotated.run, db::OpenMode::read_only);
    connection.exec("CREATE TEMP TABLE replay_step (start INTEGER, step INTEGER, x REAL, y REAL)");
    auto insert = connection.prepare("INSERT INTO temp.replay_step VALUES (?1, ?2, ?3, ?4)");
    for (const auto& [start, step, x, y] : steps) {
        insert.reset();
        insert.bind(1, start).bind(2, step).bind(3, x).bind(4, y).run();
    }
    std::string query = query_text("salient_positions.sql");
    query.erase(query.rfind(';'));
    const auto rows =
        run_query(connection,
                  "WITH w AS (" + query +
                      "\n)\nSELECT w.window_index, avg(p.x) AS x, avg(p.y) AS y, w.average_saliency\n"
                      "FROM w\nJOIN temp.replay_step AS p\n"
                      "  ON p.start = 1 AND p.step >= w.step_start AND p.step < w.step_end\n"
                      "GROUP BY w.window_index ORDER BY w.window_index",
                  {{"kb_name", std::string("run-rand")},
                   {"individual_id", annotated.best},
                   {"window", std::int64_t{50}}});
    REQUIRE(rows.size() == mean_x.size());
    for (const auto& row : rows) {
        const auto& [sum, n] = mean_x.at(static_cast<std::int64_t>(row[0].number));
        CHECK(row[1].number == Approx(sum / n));
    }
}
