// The dashboard in headless chromium: no console message, a run's curve from
// a small campaign, and a new point once one more generation is written.

#include <catch2/catch.hpp>

#include <regex>
#include <sstream>

#include "report/runs.hpp"
#include "server_process.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
namespace fs = std::filesystem;

namespace {

// the page after its scripts ran (virtual time lets the fetches finish)
std::string dump_dom(const fs::path& dir, int port, const std::string& name) {
    const auto log = dir / (name + ".log");
    const auto dom = dir / (name + ".html");
    const std::string command =
        "timeout 120 /usr/bin/chromium --headless --no-sandbox --disable-gpu --disable-quic --no-first-run "
        "--disable-background-networking --disable-component-update --disable-sync --user-data-dir='" +
        (dir / ("profile-" + name)).string() + "' --enable-logging=stderr --v=0 --virtual-time-budget=8000 --dump-dom " +
        "http://127.0.0.1:" + std::to_string(port) + "/ > '" + dom.string() + "' 2> '" + log.string() + "'";
    REQUIRE(std::system(command.c_str()) == 0);
    std::istringstream lines(test::read_file(log));
    std::string line;
    while (std::getline(lines, line)) {
        CAPTURE(line);
        CHECK(line.find(":CONSOLE") == std::string::npos);
    }
    return test::read_file(dom);
}

// the number of points of run `id`'s curve, -1 if the page has none
int curve_points(const std::string& dom, int id) {
    const std::regex curve("<polyline[^>]*data-run=\"" + std::to_string(id) + "\" data-points=\"(\\d+)\"");
    std::smatch match;
    return std::regex_search(dom, match, curve) ? std::stoi(match[1].str()) : -1;
}

}  // namespace

TEST_CASE("the dashboard shows a campaign's runs and follows a run as it grows", "[service]") {
    REQUIRE(fs::exists("/usr/bin/chromium"));
    test::TempDir dir;
    reporttest::make_campaign(dir / "camp");
    servicetest::ServerProcess server({(dir / "camp").string()}, dir.path());

    const auto first = dump_dom(dir.path(), server.port(), "first");
    // the source run (id 1): generations 0-3; a target run (id 2): 0-2
    CHECK(curve_points(first, 1) == 4);
    CHECK(curve_points(first, 2) == 3);
    CHECK(first.find("target/sum-rand/seed-2.db") != std::string::npos);
    CHECK(first.find("data-kb=\"kb\"") != std::string::npos);
    // every chart says what its axes measure: the reward curves (two charts) and each KB's histogram
    const auto count = [&](const std::string& what) {
        std::size_t n = 0;
        for (auto at = first.find(what); at != std::string::npos; at = first.find(what, at + 1)) ++n;
        return n;
    };
    CHECK(count(">best task reward so far (balls / 24)</text>") == 2);
    CHECK(count(">generation</text>") == 2);
    CHECK(count(">average reward of the segment</text>") == count("data-kb=\""));
    CHECK(count(">segments</text>") == count("data-kb=\""));
    // one thick median curve per treatment
    for (const auto* treatment : {"none", "sum", "sum-rand"}) {
        CHECK(first.find(std::string("data-treatment=\"") + treatment + "\"") != std::string::npos);
    }

    // one more generation of run 2, written while the server runs
    const auto run = dir / "camp" / "target" / "none" / "seed-1.db";
    const auto extended = test::run_cli({"evolve", "--config", (dir / "camp" / "config" / "target.json").string(),
                                         "--db", run.string(), "--resume", "--generations", "3", "--quiet"});
    INFO(extended.err);
    REQUIRE(extended.exit_code == 0);
    const auto second = dump_dom(dir.path(), server.port(), "second");
    CHECK(curve_points(second, 2) == 4);
    CHECK(server.stop() == 0);
}
