// pool reads the CSVs other tools write (RFC 4180): CRLF line ends (Python's csv
// module), a UTF-8 byte-order mark (spreadsheets), quoted fields and NA (R's
// write.csv), and names the exact problem of a file it cannot read.
#include <catch2/catch.hpp>
#include <string>

#include "runs/csv_reader.hpp"
#include "runs/pooled_stats.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using Catch::Matchers::Contains;

namespace {

const std::string kRuns =
    "treatment,seed,generation,best_reward,success,policies,ball_policies,mean_r_max\n"
    "none,1,10,0.25,0,100,0,\nsum,1,10,0.75,1,100,4,0.5\n";
const std::string kEvents =
    "treatment,seed,event,generation,observed\n"
    "none,1,press,2,1\nnone,1,pickup,10,0\nnone,1,release,10,0\nnone,1,ball,10,0\n"
    "sum,1,press,1,1\nsum,1,pickup,3,1\nsum,1,release,5,1\nsum,1,ball,10,0\n";

// every "\n" as "\r\n"
std::string crlf(const std::string& text) {
    std::string out;
    for (char c : text) out += c == '\n' ? std::string("\r\n") : std::string(1, c);
    return out;
}

// every field quoted, as R's write.csv(..., row.names = FALSE) writes text, and NA for empty
std::string r_style(const std::string& text) {
    std::string out = "\"", field;
    for (char c : text) {
        if (c == ',' || c == '\n') {
            out += (field.empty() ? std::string("NA") : field) + (c == ',' ? "\",\"" : "\"\n\"");
            field.clear();
        } else {
            field += c;
        }
    }
    return out.substr(0, out.size() - 1);  // the opening quote of a record that never comes
}

runs::PooledStats pool(const test::TempDir& dir, const std::string& runs, const std::string& events) {
    test::write_file(dir / "runs.csv", runs);
    test::write_file(dir / "events.csv", events);
    const std::vector<std::filesystem::path> r{dir / "runs.csv"}, e{dir / "events.csv"};
    return runs::pool_stats(r, e, 0.5);
}

}  // namespace

TEST_CASE("pool reads CRLF, a byte-order mark, quoted fields and NA as the plain CSV", "[runs][pool][csv]") {
    test::TempDir dir;
    const auto plain = pool(dir, kRuns, kEvents);
    REQUIRE(plain.runs.size() == 2);
    for (const auto& [name, runs, events] :
         {std::tuple<std::string, std::string, std::string>{"crlf", crlf(kRuns), crlf(kEvents)},
          {"bom", "\xEF\xBB\xBF" + kRuns, "\xEF\xBB\xBF" + kEvents},
          {"quoted", r_style(kRuns), r_style(kEvents)}}) {
        CAPTURE(name);
        const auto other = pool(dir, runs, events);
        REQUIRE(other.runs.size() == plain.runs.size());
        for (std::size_t i = 0; i < plain.runs.size(); ++i) {
            CHECK(other.runs[i].best_reward == plain.runs[i].best_reward);
            CHECK(other.runs[i].mean_r_max == plain.runs[i].mean_r_max);
            CHECK(other.runs[i].success == plain.runs[i].success);
        }
    }
    // what Python's csv.writer writes (CRLF and quotes only where needed), read back field for field
    test::write_file(dir / "py.csv", "a,b\r\n\"x, with a comma\",\"say \"\"hi\"\"\"\r\n\"two\nlines\",3\r\n");
    const auto records = runs::read_csv_records(dir / "py.csv");
    REQUIRE(records.size() == 3);
    CHECK(records[1].fields == std::vector<std::string>{"x, with a comma", "say \"hi\""});
    CHECK(records[2].fields == std::vector<std::string>{"two\nlines", "3"});
    CHECK(records[2].line == 4);  // the line the record ends on
}

TEST_CASE("pool names the exact problem of a CSV it cannot read, in one line", "[runs][pool][csv][errors]") {
    test::TempDir dir;
    test::write_file(dir / "runs.csv", kRuns);
    test::write_file(dir / "events.csv", kEvents);
    const auto fails = [&](const std::string& runs, const std::string& message) {
        test::write_file(dir / "bad.csv", runs);
        const auto result = test::run_cli(
            {"pool", "--runs", (dir / "bad.csv").string(), "--events", (dir / "events.csv").string()});
        CHECK(result.exit_code != 0);
        CHECK(result.err_lines().size() == 1);
        CHECK_THAT(result.err, Contains(message));
    };
    // one stray carriage return in the middle of line 3
    fails(
        "treatment,seed,generation,best_reward,success,policies,ball_policies,mean_r_max\n"
        "none,1,10,0.25,0,100,0,\nsum,1,10,0.75,1,10\r0,4,0.5\n",
        "line 3: a carriage return inside the line");
    // R's row names
    fails(
        "\"\",\"treatment\",\"seed\",\"generation\",\"best_reward\",\"success\",\"policies\",\"ball_"
        "policies\","
        "\"mean_r_max\"\n\"1\",\"none\",1,10,0.25,0,100,0,NA\n",
        "first column has no name");
    // a quote never closed
    fails(
        "treatment,seed,generation,best_reward,success,policies,ball_policies,mean_r_max\n"
        "none,1,10,\"0.25,0,100,0,\n",
        "quote is not closed");
    // the CLI reads a CRLF file as the plain one: the same pooled runs CSV
    test::write_file(dir / "crlf.csv", crlf(kRuns));
    for (const char* name : {"runs", "crlf"}) {
        const auto result = test::run_cli({"pool", "--runs", (dir / (std::string(name) + ".csv")).string(),
                                           "--events", (dir / "events.csv").string(), "--runs-csv",
                                           (dir / (std::string(name) + "-pooled.csv")).string()});
        REQUIRE(result.exit_code == 0);
    }
    CHECK(test::read_file(dir / "crlf-pooled.csv") == test::read_file(dir / "runs-pooled.csv"));
}
