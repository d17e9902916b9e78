// The memory a `stepstone serve` process grows by to answer bodies near its limit, and what it
// keeps afterwards (label `slow`: scripts/test runs it in its Release build, where the bounds of
// docs/service.md apply; under AddressSanitizer the same requests only check the answers).

#include <httplib.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>

#include "report/runs.hpp"
#include "server_process.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using nlohmann::json;
using servicetest::ServerProcess;

namespace {

// a line of /proc/PID/status in bytes: VmHWM (the peak resident memory so far) or VmRSS (now)
std::size_t status_bytes(pid_t pid, const std::string& field) {
    std::ifstream status("/proc/" + std::to_string(pid) + "/status");
    std::string key;
    while (status >> key) {
        if (key == field + ":") {
            std::size_t kib = 0;
            status >> kib;
            return kib * 1024;
        }
    }
    return 0;
}

std::size_t peak_rss(pid_t pid) { return status_bytes(pid, "VmHWM"); }

// the resident memory once the server has given back what it can (malloc_trim runs just after the
// answer): the least seen within `seconds`, or the first reading under `bound`
std::size_t settled_rss(pid_t pid, std::size_t bound, double seconds = 3.0) {
    std::size_t least = status_bytes(pid, "VmRSS");
    for (int i = 0; i < static_cast<int>(seconds * 20) && least >= bound; ++i) {
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
        least = std::min(least, status_bytes(pid, "VmRSS"));
    }
    return least;
}

constexpr std::size_t kMiB = std::size_t{1} << 20;

// the bounds docs/service.md states (section "Memory"), for a Release build
constexpr double kPerBody = 4.0;               // a request's peak, in times its body, above the idle server
constexpr std::size_t kIdleBound = 64 * kMiB;  // what the server keeps once answered, above its start

// a request's peak growth within the documented times its body, and the resident size back
// within the idle bound afterwards (Release only: the sanitizers' own memory would dominate)
void check_bounds(const ServerProcess& server, std::size_t before, std::size_t body_size) {
    const auto grown = peak_rss(server.pid()) - before;
    CAPTURE(body_size, grown, static_cast<double>(grown) / static_cast<double>(body_size));
#if !defined(STEPSTONE_SANITIZED_BUILD)
    CHECK(grown < static_cast<std::size_t>(kPerBody * static_cast<double>(body_size)));
    CHECK(settled_rss(server.pid(), before + kIdleBound) < before + kIdleBound);
#endif
}

httplib::Client long_client(int port) {
    httplib::Client client("127.0.0.1", port);
    client.set_read_timeout(600, 0);
    client.set_write_timeout(600, 0);
    return client;
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
    // float32 values, the answer (4.5 times the body before the SAX parse, 1.9 times since)
    CHECK(grown < static_cast<std::size_t>(kPerBody * static_cast<double>(body.size())));
#endif
    CHECK(server.stop() == 0);
}

TEST_CASE("a body nested 60 million levels deep is refused at the depth limit, in bounded memory",
          "[service]") {
    test::TempDir dir;
    reporttest::make_run(dir / "run.db");
    ServerProcess server({(dir / "run.db").string(), "--timeout", "600"}, dir.path());
    // {"segments": [[[[... : before, 2.27 GB at peak for 60 MB, 1.9 GB kept
    std::string body = "{\"segments\": [[";
    body.append(60 * kMiB - body.size() - 2, '[');
    body += "]}";
    const auto before = peak_rss(server.pid());
    const auto res = long_client(server.port()).Post("/v1/kbs/run/lookup", body, "application/json");
    REQUIRE(res);
    CHECK(res->status == 400);
    CHECK(json::parse(res->body)["error"] == "the body nests arrays and objects deeper than 64 levels");
    check_bounds(server, before, body.size());
    CHECK(server.stop() == 0);
}

TEST_CASE("a dense 60 MiB shape body costs at most the documented times its size", "[service]") {
    test::TempDir dir;
    reporttest::make_run(dir / "run.db");
    ServerProcess server({(dir / "run.db").string(), "--timeout", "600"}, dir.path());
    // the densest rows JSON has: one digit a number (before, 9.1 times the body at peak)
    std::string row = "[0";
    for (int c = 1; c < 15; ++c) row += ",0";
    row += "]";
    std::string body = "{\"behaviour\": [" + row;
    while (body.size() + row.size() + 3 < 60 * kMiB) body += "," + row;
    body += "]}";
    const auto before = peak_rss(server.pid());
    const auto res = long_client(server.port()).Post("/v1/kbs/run/shape", body, "application/json");
    REQUIRE(res);
    // 196,000 segments of 10 rows: more than a request may ask, found once the body is read
    CHECK(res->status == 413);
    CHECK(json::parse(res->body)["error"] == "behaviour has 196607 segments, more than 100000");
    check_bounds(server, before, body.size());
    CHECK(server.stop() == 0);
}

TEST_CASE("a 60 MiB body of values that are not rows of numbers is refused within the bound", "[service]") {
    test::TempDir dir;
    reporttest::make_run(dir / "run.db");
    ServerProcess server({(dir / "run.db").string(), "--timeout", "600"}, dir.path());
    // rows of unequal length: each a packed row of its own, a JSON value of about 100 bytes for
    // 4 bytes of text
    std::string body = "{\"segments\": [[0]";
    while (body.size() + 10 < 60 * kMiB) body += ",[0,0],[0]";
    body += "]}";
    const auto before = peak_rss(server.pid());
    const auto res = long_client(server.port()).Post("/v1/kbs/run/lookup", body, "application/json");
    REQUIRE(res);
    CHECK(res->status == 413);
    CHECK(json::parse(res->body)["error"].get<std::string>().rfind("the body's JSON would take more than ",
                                                                   0) == 0);
    check_bounds(server, before, body.size());
    CHECK(server.stop() == 0);
}

TEST_CASE("24 lookups of 15 MB on fresh connections stay within one request's bound and give it back",
          "[service]") {
    test::TempDir dir;
    reporttest::make_run(dir / "run.db");
    ServerProcess server({(dir / "run.db").string(), "--timeout", "600"}, dir.path());
    std::string segment = "[0.5";
    for (int v = 1; v < 150; ++v) segment += ",0.5";
    segment += "]";
    std::string body = "{\"segments\": [" + segment;
    while (body.size() + segment.size() + 3 < 15000000) body += "," + segment;
    body += "]}";
    const auto before = peak_rss(server.pid());
    std::size_t most = 0;
    for (int i = 0; i < 24; ++i) {
        // before, one allocator arena a connection's thread: 44 MB grew to 814 MB
        const auto res = long_client(server.port()).Post("/v1/kbs/run/lookup", body, "application/json");
        REQUIRE(res);
        REQUIRE(res->status == 200);
        most = std::max(most, status_bytes(server.pid(), "VmRSS"));
    }
    const auto grown = peak_rss(server.pid()) - before;
    const auto kept = settled_rss(server.pid(), before + kIdleBound);
    CAPTURE(body.size(), grown, most, kept, before);
#if !defined(STEPSTONE_SANITIZED_BUILD)
    CHECK(grown < static_cast<std::size_t>(kPerBody * static_cast<double>(body.size())));
    CHECK(kept < before + kIdleBound);
#endif
    CHECK(server.stop() == 0);
}
