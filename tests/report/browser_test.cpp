// A report opened in a real browser (Debian's chromium, headless): no console
// message, every file it loads exists inside the report, and the screenshot
// is not blank. The screenshot stays in the build tree for people to look at.

#include <catch2/catch.hpp>

#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <set>
#include <regex>
#include <sstream>

#include "images.hpp"
#include "runs.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
namespace fs = std::filesystem;

namespace {

// runs a shell command, returns its exit status; its output goes to `log`
int run_shell(const std::string& command) {
    const int status = std::system(command.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128;
}

std::string quote(const fs::path& path) { return "'" + path.string() + "'"; }

}  // namespace

TEST_CASE("the report of a campaign opens in headless chromium without errors or missing files",
          "[report][browser]") {
    REQUIRE(fs::exists("/usr/bin/chromium"));  // scripts/setup-deps installs it
    test::TempDir dir;
    reporttest::make_campaign(dir / "camp");
    const fs::path report = dir / "report";
    REQUIRE(test::run_cli({"report", (dir / "camp").string(), "--out", report.string(), "--quiet"}).exit_code == 0);

    const fs::path shot = dir / "screenshot.png";
    const fs::path log = dir / "chromium.log";
    // the flags a sandboxed root session needs; verbose logging lists every file loaded
    const std::string command =
        "timeout 120 /usr/bin/chromium --headless --no-sandbox --disable-gpu --disable-quic --no-first-run "
        "--disable-background-networking --disable-component-update --disable-sync --user-data-dir=" +
        quote(dir / "profile") + " --enable-logging=stderr --v=1 --window-size=900,3000 --screenshot=" + quote(shot) +
        " " + quote("file://" + fs::absolute(report / "index.html").string()) + " > /dev/null 2> " + quote(log);
    REQUIRE(run_shell(command) == 0);
    const std::string output = test::read_file(log);

    // no console message at all: the page has no script, so any is an error
    std::istringstream lines(output);
    std::string line;
    std::set<std::string> loaded;
    const std::regex file_load(R"(FileURLLoader::Start: file://(\S+))");
    while (std::getline(lines, line)) {
        CAPTURE(line);
        CHECK(line.find(":CONSOLE") == std::string::npos);
        std::smatch match;
        if (std::regex_search(line, match, file_load)) loaded.insert(match[1].str());
    }
    // every file the browser asked for lies in the report and exists
    const auto root = fs::canonical(report).string() + "/";
    for (const auto& path : loaded) {
        CAPTURE(path);
        CHECK(path.rfind(root, 0) == 0);
        CHECK(fs::is_regular_file(path));
    }
    // the figures were among them, the SVG trajectories included
    CHECK(loaded.count(root + "successes.png") == 1);
    CHECK(loaded.count(root + "source-best.svg") == 1);
    // the time-to-event figures
    CHECK(loaded.count(root + "kaplan-meier.png") == 1);
    CHECK(loaded.count(root + "milestone-shares.png") == 1);

    REQUIRE(fs::exists(shot));
    const auto image = reporttest::decode_png(test::read_file(shot));
    CHECK(image.width == 900);
    CHECK(image.inked() > 0.05);
    CHECK(image.colours() > 50);
    // kept for a person to look at
    std::error_code ignored;
    fs::copy_file(shot, fs::current_path() / "report-screenshot.png", fs::copy_options::overwrite_existing, ignored);
}
