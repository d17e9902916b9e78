// `stepstone serve` hardened (issue 47): a POST without a body is answered at once, a body is
// JSON whatever its Content-Type says, `Expect: 100-continue` is honoured, an IPv6 bind prints a
// URL, and --max-body is checked.

#include <arpa/inet.h>
#include <httplib.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <nlohmann/json.hpp>
#include <thread>

#include "report/runs.hpp"
#include "server_process.hpp"
#include "support/run_cli.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using nlohmann::json;
using servicetest::ServerProcess;
using Clock = std::chrono::steady_clock;

namespace {

double elapsed_since(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

// sends `request` on a fresh loopback connection and reads until the server closes it or
// `limit` seconds pass (then what came so far)
std::string exchange(int port, const std::string& request, double limit, bool close_after_send = false) {
    const int sock = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_port = htons(static_cast<std::uint16_t>(port));
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    REQUIRE(::connect(sock, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0);
    REQUIRE(::send(sock, request.data(), request.size(), MSG_NOSIGNAL) ==
            static_cast<ssize_t>(request.size()));
    if (close_after_send) ::shutdown(sock, SHUT_WR);
    std::string out;
    const auto start = Clock::now();
    char buffer[4096];
    while (elapsed_since(start) < limit) {
        pollfd fd{sock, POLLIN, 0};
        if (::poll(&fd, 1, 50) <= 0) continue;
        const auto n = ::recv(sock, buffer, sizeof buffer, 0);
        if (n <= 0) break;
        out.append(buffer, static_cast<std::size_t>(n));
        // one whole answer (our answers carry a Content-Length): enough
        const auto end = out.find("\r\n\r\n");
        const auto length_at = out.find("Content-Length: ");
        if (end != std::string::npos && length_at != std::string::npos && length_at < end &&
            out.size() >= end + 4 + std::stoul(out.substr(length_at + 16)))
            break;
    }
    ::close(sock);
    return out;
}

std::string body_of(const std::string& answer) {
    const auto end = answer.find("\r\n\r\n");
    return end == std::string::npos ? std::string() : answer.substr(end + 4);
}

}  // namespace

TEST_CASE("a POST without a body gets an immediate 400 naming the problem", "[service]") {
    test::TempDir dir;
    reporttest::make_run(dir / "run.db");
    ServerProcess server({(dir / "run.db").string()}, dir.path());
    for (const std::string length : {"", "Content-Length: 0\r\n"}) {
        CAPTURE(length);
        const auto start = Clock::now();
        // the connection stays open: before, the server waited the whole --timeout (30 s) for a body
        const auto answer = exchange(
            server.port(), "POST /v1/kbs/run/lookup HTTP/1.1\r\nHost: x\r\n" + length + "\r\n", 10.0);
        CHECK(elapsed_since(start) < 2.0);
        CAPTURE(answer);
        REQUIRE(answer.rfind("HTTP/1.1 400", 0) == 0);
        const auto error = json::parse(body_of(answer));
        CHECK(error["error"] ==
              "the request has no body: POST /v1/kbs/run/lookup takes a JSON body (and its Content-Length)");
    }
    CHECK(server.stop() == 0);
}

TEST_CASE("a body is read as JSON whatever its Content-Type, and Expect: 100-continue is honoured",
          "[service]") {
    test::TempDir dir;
    reporttest::make_run(dir / "run.db");
    ServerProcess server({(dir / "run.db").string()}, dir.path());
    // 150 values a segment; 200 segments: 120 kB, far over httplib's 8,192 bytes for a form body
    std::string body = "{\"segments\": [";
    for (int s = 0; s < 200; ++s) {
        body += s ? ",[" : "[";
        for (int v = 0; v < 150; ++v) body += v ? ",0.5" : "0.5";
        body += "]";
    }
    body += "]}";
    httplib::Client client("127.0.0.1", server.port());
    for (const char* type : {"application/x-www-form-urlencoded", "text/plain", "application/json"}) {
        CAPTURE(type);
        const auto res = client.Post("/v1/kbs/run/lookup", body, type);
        REQUIRE(res);
        CAPTURE(res->body);
        CHECK(res->status == 200);
        CHECK(json::parse(res->body)["matches"].size() == 200);
    }
    // curl sends `Expect: 100-continue` for bodies over 1 MiB and waits for the interim answer
    const auto answer = exchange(server.port(),
                                 "POST /v1/kbs/run/lookup HTTP/1.1\r\nHost: x\r\nExpect: 100-continue\r\n"
                                 "Content-Type: application/json\r\nContent-Length: " +
                                     std::to_string(body.size()) + "\r\n\r\n",
                                 0.5);
    CHECK(answer.rfind("HTTP/1.1 100 Continue\r\n", 0) == 0);
    // HEAD: GET's status and length, no body (curl -I, probes)
    const auto head = client.Head("/healthz");
    REQUIRE(head);
    CHECK(head->status == 200);
    CHECK(head->get_header_value("Content-Length") == "15");
    CHECK(head->body.empty());
    CHECK(server.stop() == 0);
}

TEST_CASE("serve --bind ::1 prints a URL with the address bracketed, and answers on it", "[service]") {
    test::TempDir dir;
    reporttest::make_run(dir / "run.db");
    ServerProcess server({(dir / "run.db").string(), "--bind", "::1"}, dir.path());
    const auto printed = test::read_file(dir / "serve.out");
    CHECK(printed.rfind("listening on http://[::1]:" + std::to_string(server.port()) + " (read-only)", 0) ==
          0);
    httplib::Client client("::1", server.port());
    const auto res = client.Get("/healthz");
    REQUIRE(res);
    CHECK(res->status == 200);
    CHECK(server.stop() == 0);
}

TEST_CASE("serve --max-body out of range, negative or not a number is refused in one line", "[service]") {
    test::TempDir dir;
    reporttest::make_run(dir / "run.db");
    for (const char* value :
         {"-1", "0", "18446744073709551616", "18446744073709551615", "1073741825", "1e6", "x"}) {
        CAPTURE(value);
        const auto result =
            test::run_cli_within({"serve", (dir / "run.db").string(), "--port", "0", "--max-body", value},
                                 std::chrono::seconds(20));
        CHECK(result.exit_code == 2);  // -1: it was serving (no limit) until killed
        REQUIRE(result.err_lines().size() == 1);
        CHECK(result.err_lines()[0] ==
              std::string("stepstone: error: --max-body must be within 1 to 1073741824 bytes, got ") + value);
    }
}

TEST_CASE("bodies held at once are bounded: beyond twice --max-body a request gets 503", "[service]") {
    test::TempDir dir;
    reporttest::make_run(dir / "run.db");
    ServerProcess server({(dir / "run.db").string(), "--max-body", "1000000"}, dir.path());
    // two requests announce 900 kB bodies and send none of it: 1.8 MB held of the 2 MB allowed
    std::vector<int> holding;
    const std::string head = "POST /v1/kbs/run/lookup HTTP/1.1\r\nHost: x\r\nContent-Length: 900000\r\n\r\n";
    for (int i = 0; i < 2; ++i) {
        const int sock = ::socket(AF_INET, SOCK_STREAM, 0);
        sockaddr_in address{};
        address.sin_family = AF_INET;
        address.sin_port = htons(static_cast<std::uint16_t>(server.port()));
        address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        REQUIRE(::connect(sock, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0);
        REQUIRE(::send(sock, head.data(), head.size(), MSG_NOSIGNAL) == static_cast<ssize_t>(head.size()));
        holding.push_back(sock);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    const auto refused = exchange(server.port(), head, 5.0);
    CAPTURE(refused);
    REQUIRE(refused.rfind("HTTP/1.1 503", 0) == 0);
    CHECK(json::parse(body_of(refused))["error"] ==
          "the server holds 1800000 bytes of request bodies (at most 2000000 at once): retry later");
    // a request without a body needs none of it
    httplib::Client client("127.0.0.1", server.port());
    const auto health = client.Get("/healthz");
    REQUIRE(health);
    CHECK(health->status == 200);
    for (const int sock : holding) ::close(sock);
    // once they are gone, a body is taken again
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    const auto res = client.Post("/v1/kbs/run/lookup", "{\"segments\": []}", "application/json");
    REQUIRE(res);
    CHECK(res->status == 200);
    CHECK(server.stop() == 0);
}
