// stepstone query (the queries/ files with headers and checked parameters) and
// stepstone export (tidy CSV), checked against the sqlite3 shell and Python's csv module.

#include <catch2/catch.hpp>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "db/database.hpp"
#include "support/db_files.hpp"
#include "support/kb_fixtures.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;
using Catch::Matchers::StartsWith;

namespace fs = std::filesystem;

namespace {

bool have(const char* program) { return std::system((std::string("command -v ") + program + " > /dev/null 2>&1").c_str()) == 0; }

std::string shell(const std::string& command) {
    std::string out;
    FILE* pipe = ::popen((command + " 2>&1").c_str(), "r");
    REQUIRE(pipe != nullptr);
    char buffer[4096];
    while (const std::size_t got = std::fread(buffer, 1, sizeof buffer, pipe)) out.append(buffer, got);
    ::pclose(pipe);
    return out;
}

std::int64_t count(const fs::path& file, const std::string& sql) {
    auto connection = db::open_database(file, db::OpenMode::read_only);
    return connection.query_int(sql).value_or(-1);
}

// Python's csv module reads the file: "<columns> <rows>\n<header>\n", or the failure
std::string python_csv(const fs::path& csv) {
    const std::string script =
        "import csv, sys\n"
        "rows = list(csv.reader(open(sys.argv[1], newline='')))\n"
        "header, data = rows[0], rows[1:]\n"
        "assert all(len(r) == len(header) for r in data), 'ragged rows'\n"
        "for r in data:\n"
        "    for name, value in zip(header, r):\n"
        "        if name not in ('task', 'treatment', 'kb', 'first_run', 'last_run', 'file') and value != '':\n"
        "            float(value)\n"
        "print(len(header), len(data))\n"
        "print(','.join(header))\n";
    const fs::path path = csv.parent_path() / "check.py";
    test::write_file(path, script);
    return shell("python3 '" + path.string() + "' '" + csv.string() + "'");
}

}  // namespace

TEST_CASE("query runs a queries/ file with a header row, as the sqlite3 shell prints it", "[cli][query]") {
    test::TempDir dir;
    kbtest::make_run(dir / "run.db");
    const auto run = (dir / "run.db").string();
    auto result = test::run_cli({"query", run, "salient_segments", "--param", "kb_name=run", "--param",
                                 "min_count=1", "--param", "limit=5"});
    INFO(result.err);
    REQUIRE(result.exit_code == 0);
    CHECK_THAT(result.out, StartsWith("kb_segment_id|average_reward|count|cum_reward"));
    std::size_t lines = 0;
    for (char c : result.out) lines += c == '\n' ? 1 : 0;
    CHECK(lines == 1 + 5);  // the tiny run's KB has more than 5 segments
    if (have("sqlite3")) {
        const std::string shell_out =
            shell("sqlite3 -header '" + run + "' \".parameter set :kb_name 'run'\" \".parameter set :min_count 1\" "
                  "\".parameter set :limit 5\" \".read " + std::string(STEPSTONE_SOURCE_DIR) +
                  "/queries/salient_segments.sql\"");
        CHECK(result.out == shell_out);
    }

    // a query without parameters, and --list
    result = test::run_cli({"query", run, "generation_times.sql"});
    CHECK(result.exit_code == 0);
    CHECK_THAT(result.out, StartsWith("run_id|generations|evaluations_per_s|"));
    result = test::run_cli({"query", "--list"});
    CHECK(result.exit_code == 0);
    for (const char* name : {"generation_times", "kb_growth", "kb_provenance", "milestones",
                             "policy_saliency", "salient_positions", "salient_segments"}) {
        CHECK_THAT(result.out, Contains(std::string(name) + ": "));
    }
    // a description runs to the end of its first sentence, past "Fig. 5" (queries/policy_saliency.sql)
    CHECK_THAT(result.out, Contains("(the paper's Fig. 5): for each segment of a stored policy, the average "
                                    "reward of the KB segment it matched."));
}

TEST_CASE("query checks its parameters and names the problem", "[cli][query][errors]") {
    test::TempDir dir;
    kbtest::make_run(dir / "run.db");
    const auto run = (dir / "run.db").string();
    const auto refused = [](const test::CliResult& result, const std::string& needle) {
        INFO(result.err);
        CHECK(result.exit_code == 2);
        REQUIRE(result.err_lines().size() == 1);
        CHECK_THAT(result.err_lines()[0], Contains(needle));
        CHECK(result.out.empty());
    };
    refused(test::run_cli({"query", run, "salient_segments", "--param", "kb_name=run"}), "needs --param min_count");
    refused(test::run_cli({"query", run, "kb_growth", "--param", "kb_name=run", "--param", "limt=3"}),
            "has no parameter :limt (its parameters: :kb_name)");
    refused(test::run_cli({"query", run, "kb_growth", "--param", "kb_name"}), "--param must be NAME=VALUE");
    refused(test::run_cli({"query", run, "no_such_query"}), "queries: generation_times, kb_growth");
    auto missing = test::run_cli({"query", (dir / "absent.db").string(), "kb_growth", "--param", "kb_name=run"});
    CHECK(missing.exit_code == 1);
    CHECK_THAT(missing.err, Contains((dir / "absent.db").string() + ": no such file"));
    // a KB name the file does not hold: one line naming the ones it does, not an empty table
    const auto unknown = test::run_cli({"query", run, "kb_growth", "--param", "kb_name=other"});
    CHECK(unknown.exit_code == 1);
    REQUIRE(unknown.err_lines().size() == 1);
    CHECK_THAT(unknown.err, Contains("no knowledge base named \"other\" (its KBs: run)"));
    CHECK(unknown.out.empty());
}

TEST_CASE("query --list gives each query's whole first sentence", "[cli][query]") {
    const auto list = test::run_cli({"query", "--list"});
    REQUIRE(list.exit_code == 0);
    // queries/kb_growth.sql's first sentence spans two comment lines
    CHECK_THAT(list.out,
               Contains("kb_growth: KB growth per generation: how many segments each observed generation "
                        "inserted into a knowledge base, and the KB's size after it.\n"));
}

TEST_CASE("export writes tidy CSV that Python's csv module reads, of a run and of a campaign", "[cli][export]") {
    test::TempDir dir;
    kbtest::make_run(dir / "run.db");
    const auto run = (dir / "run.db").string();
    for (const char* what : {"generations", "individuals", "kb"}) {
        auto result = test::run_cli({"export", run, "--what", what, "--csv", (dir / (std::string(what) + ".csv")).string()});
        INFO(what << ": " << result.err);
        REQUIRE(result.exit_code == 0);
    }
    const std::string generations = test::read_file(dir / "generations.csv");
    CHECK_THAT(generations, StartsWith("task,treatment,seed,generation,best_reward,mean_reward,median_reward,"
                                       "first_front_size,fronts,"));
    CHECK_THAT(generations, Contains("\nsource,none,3,0,"));
    // generation 0's individuals have no parent: an empty field
    CHECK_THAT(test::read_file(dir / "individuals.csv"), Contains("\nsource,none,3,0,0,,"));
    // the milestones close each row
    CHECK_THAT(test::read_file(dir / "individuals.csv"),
               Contains(",balls,steps,presses,pickups,carry_steps,basket_releases\n"));

    const auto rows_of = [&](const std::string& text) {
        std::size_t lines = 0;
        for (char c : text) lines += c == '\n' ? 1 : 0;
        return static_cast<std::int64_t>(lines) - 1;
    };
    CHECK(rows_of(generations) == count(dir / "run.db", "SELECT COUNT(*) FROM generation"));
    CHECK(rows_of(test::read_file(dir / "individuals.csv")) == count(dir / "run.db", "SELECT COUNT(*) FROM individual"));
    CHECK(rows_of(test::read_file(dir / "kb.csv")) == count(dir / "run.db", "SELECT COUNT(*) FROM kb_segment"));

    // a campaign: every run, told apart by task, treatment and seed
    fs::create_directories(dir / "camp" / "source");
    fs::copy_file(dir / "run.db", dir / "camp" / "source" / "seed-3.db");
    fs::copy_file(dir / "run.db", dir / "camp" / "source" / "seed-4.db");
    {
        db::OutputDatabase out(dir / "camp" / "campaign.db", false);
        out.connection().exec(
            "INSERT INTO campaign (id, config, created) VALUES (1, '{}', '2026-01-01T00:00:00Z');"
            "INSERT INTO campaign_run (id, step, treatment, seed, file, generations, status) VALUES "
            "(1, 'source', 'none', 3, 'source/seed-3.db', 3, 'finished'),"
            "(2, 'source', 'none', 4, 'source/seed-4.db', 3, 'finished'),"
            "(3, 'target', 'sum', 3, 'target/sum/seed-3.db', 3, 'pending')");
        out.commit();
    }
    auto result = test::run_cli({"export", (dir / "camp").string(), "--what", "individuals", "--csv",
                                 (dir / "camp.csv").string()});
    INFO(result.err);
    REQUIRE(result.exit_code == 0);
    const std::string campaign = test::read_file(dir / "camp.csv");
    CHECK(rows_of(campaign) == 2 * count(dir / "run.db", "SELECT COUNT(*) FROM individual"));
    CHECK_THAT(campaign, Contains("\nsource,none,4,"));

    // an existing output needs --force, a missing folder is refused before any work
    CHECK(test::run_cli({"export", run, "--what", "kb", "--csv", (dir / "kb.csv").string()}).exit_code == 2);
    CHECK(test::run_cli({"export", run, "--what", "kb", "--csv", "/no/such/dir/kb.csv"}).exit_code == 2);
    CHECK(test::run_cli({"export", run, "--what", "genomes", "--csv", (dir / "x.csv").string()}).exit_code == 2);

    if (!have("python3")) {
        WARN("no python3: the CSV files were checked in C++ only");
        return;
    }
    const std::string g = python_csv(dir / "generations.csv");
    INFO(g);
    CHECK_THAT(g, StartsWith("18 " + std::to_string(count(dir / "run.db", "SELECT COUNT(*) FROM generation")) + "\n"));
    const std::string c = python_csv(dir / "camp.csv");
    // 3 run columns, the 9 individual columns and the 4 milestones
    INFO(c);
    CHECK_THAT(c, StartsWith("16 " + std::to_string(rows_of(campaign)) +
                             "\ntask,treatment,seed,id,generation,parent_id,"));
    const std::string k = python_csv(dir / "kb.csv");
    INFO(k);
    CHECK_THAT(k, Contains("kb,segment,count,cum_reward,average_reward,first_run,first_generation,last_run,"));
}

TEST_CASE("export reads a file older than the milestones as it is: their columns are empty",
          "[cli][export][milestones]") {
    test::TempDir dir;
    kbtest::make_run(dir / "run.db");
    test::make_schema4_run(dir / "run.db");  // schema 4 had no milestone columns
    const auto before = test::read_file(dir / "run.db");
    const auto result = test::run_cli(
        {"export", (dir / "run.db").string(), "--what", "individuals", "--csv", (dir / "i.csv").string()});
    INFO(result.err);
    REQUIRE(result.exit_code == 0);
    const auto csv = test::read_file(dir / "i.csv");
    CHECK_THAT(csv, Contains(",presses,pickups,carry_steps,basket_releases\n"));
    // every row ends in four empty fields
    std::size_t rows = 0, empty_tails = 0;
    for (std::size_t at = csv.find('\n') + 1; at < csv.size(); at = csv.find('\n', at) + 1) {
        const auto end = csv.find('\n', at);
        ++rows;
        empty_tails += csv.compare(end - 4, 4, ",,,,") == 0 ? 1 : 0;
    }
    CHECK(rows > 0);
    CHECK(empty_tails == rows);
    CHECK(test::read_file(dir / "run.db") == before);  // read-only: the file is untouched
}
