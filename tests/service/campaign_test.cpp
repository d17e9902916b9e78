// A campaign directory served while the campaign goes on (issue 47 item 8): KBs made after the
// server started are served, and a run whose file was deleted answers 410 naming it.

#include <httplib.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <nlohmann/json.hpp>
#include <thread>

#include "db/database.hpp"
#include "report/runs.hpp"
#include "server_process.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using nlohmann::json;
using servicetest::ServerProcess;

TEST_CASE("a served campaign shows KBs made after the start, and a deleted run is gone (410)", "[service]") {
    test::TempDir dir;
    reporttest::make_campaign(dir / "camp");
    // the campaign as it was before its KB step: the KB files not there yet
    std::vector<std::string> kb_files;
    {
        auto connection = db::open_database(dir / "camp" / "campaign.db", db::OpenMode::read_only);
        auto rows = connection.prepare("SELECT file FROM campaign_kb ORDER BY name");
        while (rows.step()) kb_files.push_back(rows.column_text(0));
    }
    REQUIRE(kb_files.size() == 2);
    const auto aside = [&](const std::string& file) { return dir / std::filesystem::path(file).filename(); };
    for (const auto& file : kb_files) std::filesystem::rename(dir / "camp" / file, aside(file));
    ServerProcess server({(dir / "camp").string()}, dir.path());
    httplib::Client client("127.0.0.1", server.port());
    const auto get = [&](const std::string& path, int status) {
        const auto res = client.Get(path.c_str());
        REQUIRE(res);
        CAPTURE(path, res->body);
        CHECK(res->status == status);
        return json::parse(res->body);
    };
    CHECK(get("/v1/kbs", 200).empty());
    // the KB step ends: its files appear, and within a rescan the KBs are served
    for (const auto& file : kb_files) std::filesystem::rename(aside(file), dir / "camp" / file);
    const auto start = std::chrono::steady_clock::now();
    json kbs = json::array();
    while (kbs.size() < 2 &&
           std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() < 5.0) {
        std::this_thread::sleep_for(std::chrono::milliseconds(200));
        kbs = get("/v1/kbs", 200);
    }
    CHECK(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() < 3.0);
    REQUIRE(kbs.size() == 2);
    CHECK(get("/v1/campaign", 200)["kbs"].size() == 2);
    CHECK(get("/v1/kbs/kb", 200)["segments"].get<std::size_t>() > 0);
    // a run file deleted while served: 410 naming it, not an empty list
    const auto runs = get("/v1/runs", 200);
    REQUIRE_FALSE(runs.empty());
    const auto id = runs[0]["id"].get<std::int64_t>();
    const std::string file = runs[0]["file"];
    const auto name = std::filesystem::path(file).filename().string();
    CHECK(get("/v1/runs/" + std::to_string(id) + "/generations", 200).size() > 0);
    std::filesystem::remove(dir / "camp" / file);
    const auto gone = get("/v1/runs/" + std::to_string(id) + "/generations", 410);
    CHECK(gone["error"] ==
          "run " + std::to_string(id) + ": its file " + name + " is gone (deleted while served)");
    CHECK(server.stop() == 0);
}
