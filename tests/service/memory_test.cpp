// The memory a `stepstone serve` process grows by to answer a body near its limit (label `slow`:
// scripts/test runs it in its Release build, where the bound applies; under AddressSanitizer the
// same request only checks the answer).

#include <httplib.h>

#include <catch2/catch.hpp>
#include <fstream>
#include <nlohmann/json.hpp>

#include "report/runs.hpp"
#include "server_process.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using nlohmann::json;
using servicetest::ServerProcess;

namespace {

// the peak resident memory of process `pid` so far (VmHWM), in bytes
std::size_t peak_rss(pid_t pid) {
    std::ifstream status("/proc/" + std::to_string(pid) + "/status");
    std::string key;
    while (status >> key) {
        if (key == "VmHWM:") {
            std::size_t kib = 0;
            status >> kib;
            return kib * 1024;
        }
    }
    return 0;
}

}  // namespace

TEST_CASE("a shape body near the body limit costs a few times its size in memory", "[service]") {
    test::TempDir dir;
    reporttest::make_run(dir / "run.db");
    // the default 64 MiB body limit; a request time far above the default 30 s, which a sanitized
    // server (STEPSTONE_SANITIZE_ALL_TESTS) on a loaded machine can take to read and answer this
    // body (a test of memory, not time)
    ServerProcess server({(dir / "run.db").string(), "--timeout", "600"}, dir.path());
    // 900,000 rows of 15 channels (90,000 segments of 10 rows; 100,000 is the most a request may ask): 62 MB
    std::string body = "{\"behaviour\": [";
    const std::string row = "[0.5,0.25,0.5,0.25,0.5,0.25,0.5,0.25,0.5,0.25,0.5,0.25,0.5,0.25,0.5]";
    for (int r = 0; r < 900000; ++r) body += (r ? "," : "") + row;
    body += "]}";
    REQUIRE(body.size() < (64u << 20));
    const auto before = peak_rss(server.pid());
    REQUIRE(before > 0);
    httplib::Client client("127.0.0.1", server.port());
    client.set_read_timeout(600, 0);
    client.set_write_timeout(600, 0);
    const auto res = client.Post("/v1/kbs/run/shape", body, "application/json");
    REQUIRE(res);
    REQUIRE(res->status == 200);
    CHECK(json::parse(res->body)["matches"].size() == 90000);
    const auto grown = peak_rss(server.pid()) - before;
    CAPTURE(body.size(), grown);
#if defined(STEPSTONE_SANITIZED_BUILD)
    // AddressSanitizer's redzones and quarantine inflate every allocation: the bound is the release build's
    SUCCEED("not bounded under AddressSanitizer");
#else
    // the DOM of numbers alone was 13 times the body (796 MB for 61 MB); packed rows: the body, its
    // float32 values, the answer
    CHECK(grown < 6 * body.size());
#endif
    CHECK(server.stop() == 0);
}
