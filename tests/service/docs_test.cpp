// Every curl and Python example of docs/service.md, run as written against live servers on
// loopback: `stepstone serve run.db` for the examples on port 8080 and `stepstone serve kb.db
// --writable --token-file token.txt` for those on port 9000 (each on a free port, put in place of
// 8080 and 9000). The files the examples read (run.db, kb.db, token.txt, and the examples/ folder)
// are made or linked by the test; every other file is made by the examples themselves. curl is
// the real one (scripts/setup-deps installs it); where it is absent, curl_fallback.py stands in.

#include <catch2/catch.hpp>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>

#include "report/runs.hpp"
#include "server_process.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using nlohmann::json;

namespace {

// the commands of the ```sh blocks (a line ending in '\' continues on the next)
std::vector<std::string> shell_commands(const std::string& markdown) {
    std::vector<std::string> out;
    std::istringstream in(markdown);
    std::string line, command;
    bool in_block = false;
    while (std::getline(in, line)) {
        if (line.rfind("```", 0) == 0) {
            in_block = !in_block && line == "```sh";
            continue;
        }
        if (!in_block) continue;
        command += line;
        if (!command.empty() && command.back() == '\\') {
            command.pop_back();
            continue;
        }
        out.push_back(command);
        command.clear();
    }
    return out;
}

std::string substitute_all(std::string text, const std::string& from, const std::string& to) {
    for (auto at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size()))
        text.replace(at, from.size(), to);
    return text;
}

}  // namespace

TEST_CASE("every curl and Python example of docs/service.md runs as written", "[service]") {
    REQUIRE(std::system("python3 --version > /dev/null 2>&1") == 0);  // scripts/setup-deps installs it
    test::TempDir dir;
    // curl comes with scripts/setup-deps and nothing is installed here: without it (or with
    // STEPSTONE_TEST_NO_CURL=1) the curl lines run through curl_fallback.py, which sends the same
    // bytes and headers with Python's urllib
    std::string path_prefix;
    if (std::getenv("STEPSTONE_TEST_NO_CURL") || std::system("curl --version > /dev/null 2>&1") != 0) {
        WARN("curl is absent: the examples' curl lines are sent by tests/service/curl_fallback.py (urllib)");
        std::filesystem::create_directory(dir / "fallback");
        std::filesystem::create_symlink(
            std::filesystem::path(STEPSTONE_SOURCE_DIR) / "tests" / "service" / "curl_fallback.py",
            dir / "fallback" / "curl");
        path_prefix = "export PATH='" + (dir / "fallback").string() + "':\"$PATH\" && ";
    }
    reporttest::make_run(dir / "run.db");
    REQUIRE(test::run_cli({"kb", "export", (dir / "run.db").string(), "--out", (dir / "kb.db").string()})
                .exit_code == 0);
    test::write_file(dir / "token.txt", "a-long-enough-secret-token\n");
    std::filesystem::create_directory_symlink(std::filesystem::path(STEPSTONE_SOURCE_DIR) / "examples",
                                              dir / "examples");
    servicetest::ServerProcess reader({(dir / "run.db").string()}, dir.path());
    const auto writer_dir = dir / "writer";
    std::filesystem::create_directory(writer_dir);
    servicetest::ServerProcess writer(
        {(dir / "kb.db").string(), "--writable", "--token-file", (dir / "token.txt").string()}, writer_dir);

    const auto commands =
        shell_commands(test::read_file(std::filesystem::path(STEPSTONE_SOURCE_DIR) / "docs" / "service.md"));
    // the files the examples make first (a redirection, stepstone replay), then the requests in order
    std::vector<std::string> making, asking;
    for (const auto& command : commands) {
        if (command.rfind("curl ", 0) == 0 || command.rfind("python3 examples/", 0) == 0) {
            asking.push_back(command);
        } else if (command.rfind("python3 ", 0) == 0 || command.rfind("stepstone replay ", 0) == 0) {
            making.push_back(command);
        }
    }
    CHECK(making.size() >= 3);
    CHECK(asking.size() >= 11);
    const std::string bin_dir = std::filesystem::path(STEPSTONE_BINARY).parent_path().string();
    int curls = 0;
    for (const auto& written : making) {
        CAPTURE(written);
        // a subshell, so that the example's own redirection and comment stand as written
        const std::string shell = "cd '" + dir.path().string() + "' && export PATH='" + bin_dir +
                                  "':\"$PATH\" && (" + written + "\n) > /dev/null 2> made.err";
        CHECK(std::system(shell.c_str()) == 0);
    }
    for (const auto& written : asking) {
        auto command =
            substitute_all(written, "127.0.0.1:8080", "127.0.0.1:" + std::to_string(reader.port()));
        command = substitute_all(command, "127.0.0.1:9000", "127.0.0.1:" + std::to_string(writer.port()));
        CAPTURE(written, command);
        const std::string shell =
            "cd '" + dir.path().string() + "' && (" + command + "\n) > answer.out 2> answer.err";
        REQUIRE(std::system(shell.c_str()) == 0);
        const auto answer = test::read_file(dir / "answer.out");
        CAPTURE(answer, test::read_file(dir / "answer.err"));
        if (command.rfind("curl ", 0) != 0) {
            CHECK(answer.find("r_max ") != std::string::npos);  // kb_client.py's last line
            continue;
        }
        ++curls;
        const auto parsed = json::parse(answer, nullptr, false);
        REQUIRE_FALSE(parsed.is_discarded());
        // an error only where the example says which one it shows
        std::smatch shown;
        if (std::regex_search(written, shown, std::regex("# (4\\d\\d)"))) {
            REQUIRE(parsed.is_object());
            CHECK(parsed["status"] == std::stoi(shown[1].str()));
        } else {
            CHECK_FALSE((parsed.is_object() && parsed.contains("error")));
        }
        if (command.find("/observe") != std::string::npos) CHECK(parsed["durable"] == true);
    }
    CHECK(curls >= 10);
    CHECK(reader.stop() == 0);
    CHECK(writer.stop() == 0);
}
