// Bad-input fuzzing: generated configs, flags and database files. Every bad
// case ends with exit 1 or 2 and exactly one "stepstone: error:" line (never
// 70, a signal or a hang), and no input file changes by a byte.

#include <catch2/catch.hpp>
#include <chrono>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <random>

#include "support/db_files.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
namespace fs = std::filesystem;

namespace {

/// Runs the cases and checks the contract; counts the cases that had to fail.
class Fuzzer {
public:
    explicit Fuzzer(const fs::path& scratch) : scratch_(scratch) {}

    /// `inputs` must be unchanged afterwards; `may_succeed`: exit 0 is fine too (a valid
    /// mutation, a bit flip in unused bytes).
    void check(const std::string& label, const std::vector<std::string>& args, const std::vector<fs::path>& inputs,
               bool may_succeed = false) {
        std::map<fs::path, std::string> before;
        for (const auto& input : inputs) before[input] = fs::exists(input) && fs::is_regular_file(input) ? test::read_file(input) : "";
        const test::CliResult outcome = test::run_cli_within(args, std::chrono::seconds(20));
        ++cases_;
        if (outcome.exit_code != 0 || !may_succeed) ++bad_cases_;
        std::string problem;
        if (outcome.exit_code == -1) {
            problem = "hung (killed after 20 s)";
        } else if (outcome.exit_code == 0 && !may_succeed) {
            problem = "accepted (exit 0)";
        } else if (outcome.exit_code != 0 && outcome.exit_code != 1 && outcome.exit_code != 2) {
            problem = "exit " + std::to_string(outcome.exit_code);
        } else if (outcome.exit_code != 0) {
            const auto first = outcome.err.find('\n');
            if (outcome.err.rfind("stepstone: error: ", 0) != 0 || first + 1 != outcome.err.size()) {
                problem = "stderr is not one error line";
            }
        }
        for (const auto& [input, bytes] : before) {
            if (fs::is_regular_file(input) && test::read_file(input) != bytes) problem += " changed " + input.string();
        }
        if (!problem.empty()) {
            std::string command;
            for (const auto& arg : args) command += " " + arg;
            failures_.push_back(label + ":" + command + ": " + problem + ": " + outcome.err);
        }
    }

    int cases() const { return cases_; }
    int bad_cases() const { return bad_cases_; }
    const std::vector<std::string>& failures() const { return failures_; }

private:
    fs::path scratch_;
    int cases_ = 0;
    int bad_cases_ = 0;
    std::vector<std::string> failures_;
};

void report(const Fuzzer& fuzzer, int at_least) {
    INFO(fuzzer.cases() << " cases, " << fuzzer.bad_cases() << " refused as they should be");
    for (std::size_t k = 0; k < std::min<std::size_t>(fuzzer.failures().size(), 30); ++k) {
        FAIL_CHECK(fuzzer.failures()[k]);
    }
    CHECK(fuzzer.failures().empty());
    CHECK(fuzzer.bad_cases() >= at_least);
}

const nlohmann::json kBaseConfig = nlohmann::json::parse(R"({
  "task": {"kind": "source", "steps_per_start": 100, "starts": 1},
  "ea": {"population_size": 8, "generations": 1},
  "kb": {"segment_width": 10, "delta": 1.0, "period": 1},
  "seed": 1
})");

}  // namespace

TEST_CASE("fuzzed configs and flags are refused with one line, exit 1 or 2, inputs unchanged",
          "[reliability][slow][fuzz]") {
    test::TempDir dir;
    Fuzzer fuzzer(dir.path());
    const auto out = (dir / "out.db").string();
    const auto evolve = [&](const fs::path& config) {
        return std::vector<std::string>{"evolve", "--config", config.string(), "--db", out, "--generations", "0",
                                        "--threads", "1", "--quiet", "--force"};
    };

    // every value of the config replaced by values of every other type and extremes
    const std::vector<std::string> paths{"/task/kind", "/task/steps_per_start", "/task/starts",
                                         "/ea/population_size", "/ea/generations", "/kb/segment_width",
                                         "/kb/delta", "/kb/period", "/seed", "/task", "/ea", "/kb"};
    const std::vector<std::string> values{"null", "true", "\"text\"", "\"\"", "-1", "0", "1.5", "-1e308", "1e308",
                                          "9223372036854775807", "-9223372036854775808", "18446744073709551615",
                                          "[]", "[1, 2]", "{}", "{\"x\": 1}", "3", "4000000000"};
    int n = 0;
    for (const auto& path : paths) {
        for (const auto& value : values) {
            nlohmann::json config = kBaseConfig;
            config[nlohmann::json::json_pointer(path)] = nlohmann::json::parse(value);
            const auto file = dir / ("c" + std::to_string(n++) + ".json");
            test::write_file(file, config.dump());
            // some mutations are valid (3 starts, delta 1e308): they must then run and end, not hang;
            // the others must be refused with one line
            fuzzer.check("config " + path + " = " + value, evolve(file), {file}, true);
            fs::remove(out);
        }
    }
    // unknown keys at every level, non-numbers JSON does not have, broken text
    for (const auto& path : {"/bogus", "/task/bogus", "/ea/bogus", "/kb/bogus", "/task/Kind", "/ea/population"}) {
        nlohmann::json config = kBaseConfig;
        config[nlohmann::json::json_pointer(path)] = 1;
        const auto file = dir / ("u" + std::to_string(n++) + ".json");
        test::write_file(file, config.dump());
        fuzzer.check(std::string("unknown key ") + path, evolve(file), {file});
    }
    const std::string text = kBaseConfig.dump();
    std::vector<std::string> texts{"", " ", "null", "[]", "42", "\"config\"", std::string(20000, '['),
                                   std::string("\x00\x01\x02\xff", 4), "{\"task\": NaN}", "{\"seed\": Infinity}",
                                   "{\"seed\": 1e400}", "{\"task\": {\"steps_per_start\": 1e999}}"};
    for (std::size_t cut = 1; cut < text.size(); cut += 5) texts.push_back(text.substr(0, cut));
    for (const auto& bad : texts) {
        const auto file = dir / ("t" + std::to_string(n++) + ".json");
        test::write_file(file, bad);
        fuzzer.check("config text", evolve(file), {file});
        fs::remove(out);
    }
    fuzzer.check("missing config", evolve(dir / "absent.json"), {});
    fuzzer.check("directory config", evolve(dir.path()), {});
    const auto campaign_config = dir / "camp.json";
    test::write_file(campaign_config, R"({"target": {"config": {"task": {"kind": "target"}}, "seeds": [1]}})");
    fuzzer.check("campaign config to evolve", evolve(campaign_config), {campaign_config});
    const auto good = dir / "good.json";
    test::write_file(good, kBaseConfig.dump());
    fuzzer.check("run config to campaign", {"campaign", good.string(), "--dir", (dir / "camp").string()}, {good});

    // flags: wrong types, out of range, unknown, missing values
    const std::vector<std::vector<std::string>> flag_cases{
        {"--generations", "-5"}, {"--generations", "abc"}, {"--generations", "1e99"}, {"--generations", ""},
        {"--threads", "-1"}, {"--threads", "abc"}, {"--threads", "99999999999"}, {"--seed", "abc"},
        {"--seed", "-1"}, {"--seed", "1e30"}, {"--seed", "18446744073709551616"}, {"--retain", "some"},
        {"--treatment", "best"}, {"--treatment", "sum"}, {"--kb", (dir / "absent.db").string()},
        {"--kb", good.string()}, {"--bogus"}, {"--resume", "--force"}, {"--seed"}, {"--db"}};
    for (const auto& flags : flag_cases) {
        std::vector<std::string> args{"evolve", "--config", good.string(), "--db", out, "--quiet"};
        args.insert(args.end(), flags.begin(), flags.end());
        fuzzer.check("evolve flags", args, {good});
        fs::remove(out);
    }
    const std::vector<std::vector<std::string>> commands{
        {"simulate", "--task", "moon", "--controller", "random", "--csv", (dir / "s.csv").string()},
        {"simulate", "--task", "source", "--controller", "random", "--steps", "-1", "--csv", (dir / "s.csv").string()},
        {"simulate", "--task", "source", "--controller", "random", "--steps", "abc", "--csv", (dir / "s.csv").string()},
        {"simulate", "--task", "source", "--controller", "random", "--starts", "0", "--csv", (dir / "s.csv").string()},
        {"simulate", "--task", "source", "--controller", "random", "--csv", "/no/such/dir/s.csv"},
        {"stats", dir.path().string(), "--threshold", "nan"}, {"stats", dir.path().string(), "--threshold", "2"},
        {"stats", dir.path().string(), "--threshold", "-1"}, {"stats", (dir / "absent").string()},
        {"kb", "randomize", good.string(), "--out", (dir / "r.db").string(), "--seed", "-1"},
        {"kb", "merge", good.string(), "--out", (dir / "m.db").string()},
        {"kb", "calibrate", good.string(), "--deltas", "0,-1"}, {"kb", "calibrate", good.string(), "--deltas", "nan"},
        {"query", good.string(), "nothing"}, {"query", good.string()}, {"export", good.string(), "--what", "x",
                                                                        "--csv", (dir / "x.csv").string()},
        {"db", "info"}, {"db", "digest", good.string()}, {"replay", good.string()},
        {"evolv"}, {"kb", "exprot"}, {"db"}, {"campaign", good.string()}, {"demo", "--dir", good.string()},
        {"report", good.string(), "--out", (dir / "rep").string()}, {"bench", "nothing"}};
    for (const auto& args : commands) fuzzer.check("command", args, {good});
    report(fuzzer, 250);
}

TEST_CASE("fuzzed database files are refused with one line, never a crash, never changed",
          "[reliability][slow][fuzz]") {
    test::TempDir dir;
    Fuzzer fuzzer(dir.path());
    test::write_file(dir / "c.json", kBaseConfig.dump());
    REQUIRE(test::run_cli({"evolve", "--config", (dir / "c.json").string(), "--db", (dir / "run.db").string(),
                           "--quiet"})
                .exit_code == 0);
    REQUIRE(test::run_cli({"kb", "export", (dir / "run.db").string(), "--out", (dir / "kb.db").string()})
                .exit_code == 0);
    const std::string run_bytes = test::read_file(dir / "run.db");
    const std::string kb_bytes = test::read_file(dir / "kb.db");

    // the variants: truncated, bit-flipped, foreign, newer, empty, text, and each file where the other is expected
    std::vector<std::pair<fs::path, bool>> files;  // path, whether a command may still succeed on it
    std::mt19937 draw(500);
    for (const auto& [name, bytes] : {std::pair<std::string, std::string>{"run", run_bytes}, {"kb", kb_bytes}}) {
        for (int k = 1; k <= 10; ++k) {
            const auto path = dir / (name + "-cut" + std::to_string(k) + ".db");
            test::write_file(path, bytes.substr(0, bytes.size() * static_cast<std::size_t>(k) / 11));
            files.emplace_back(path, false);
        }
        std::uniform_int_distribution<std::size_t> where(0, bytes.size() - 1);
        for (int k = 0; k < 24; ++k) {
            std::string flipped = bytes;
            const std::size_t at = k < 4 ? static_cast<std::size_t>(16 + k * 20) : where(draw);  // the header too
            flipped[at] = static_cast<char>(flipped[at] ^ (1 << (k % 8)));
            const auto path = dir / (name + "-flip" + std::to_string(k) + ".db");
            test::write_file(path, flipped);
            files.emplace_back(path, true);
        }
    }
    test::make_foreign_sqlite(dir / "foreign.db");
    test::make_newer_stepstone(dir / "newer.db");
    test::make_stepstone_db(dir / "other.db");  // a stepstone file with neither run nor KB
    test::write_file(dir / "empty.db", "");
    test::write_file(dir / "text.db", "SQLite format 3 but not really\n");
    for (const char* name : {"foreign.db", "newer.db", "empty.db", "text.db"}) files.emplace_back(dir / name, false);
    files.emplace_back(dir / "other.db", true);  // db info and the queries read it; run and KB commands refuse it
    files.emplace_back(dir / "kb.db", true);  // a KB where a run is expected: refused by run commands

    const auto out = (dir / "out.db").string();
    for (const auto& [file, may_succeed] : files) {
        const std::string path = file.string();
        const bool kb_file = file.filename().string().rfind("kb", 0) == 0;
        const std::vector<std::pair<std::vector<std::string>, bool>> commands{
            {{"db", "info", path}, may_succeed},
            {{"db", "digest", path}, may_succeed && !kb_file},
            {{"replay", path, "--individual", "best"}, may_succeed && !kb_file},
            {{"kb", "stats", path}, may_succeed},
            {{"kb", "export", path, "--out", out, "--force"}, may_succeed},
            {{"query", path, "generation_times"}, may_succeed},
            {{"export", path, "--what", "individuals", "--csv", (dir / "out.csv").string(), "--force"},
             may_succeed && !kb_file},
            {{"shape", "--kb", path, "--run", (dir / "run.db").string(), "--individual", "best"}, may_succeed},
        };
        for (const auto& [args, ok] : commands) {
            fuzzer.check(file.filename().string(), args, {file, dir / "run.db"}, ok);
            fs::remove(out);
        }
    }
    CHECK(test::read_file(dir / "run.db") == run_bytes);
    report(fuzzer, 250);
}
