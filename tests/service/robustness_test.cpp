// `stepstone serve` against clients that misbehave, on loopback: slow clients
// (slowloris), a bounded fuzz of paths, queries, headers and bodies, and a
// client that reuses its connection.

#include <arpa/inet.h>
#include <httplib.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <catch2/catch.hpp>
#include <chrono>
#include <nlohmann/json.hpp>
#include <random>
#include <thread>

#include "report/runs.hpp"
#include "server_process.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using nlohmann::json;
using servicetest::ServerProcess;
using Clock = std::chrono::steady_clock;

namespace {

double seconds_since(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

// a raw TCP connection to the server on loopback (-1 if it cannot connect)
int connect_to(int port) {
    const int sock = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_port = htons(static_cast<std::uint16_t>(port));
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (::connect(sock, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) {
        ::close(sock);
        return -1;
    }
    return sock;
}

// A client that sends a request's header one byte every `pause`, never
// finishing it, until told to stop or the server closes the connection.
class SlowClient {
public:
    SlowClient(int port, std::chrono::milliseconds pause) : sock_(connect_to(port)) {
        thread_ = std::thread([this, pause] {
            const std::string header =
                "GET /healthz HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Slow: " + std::string(10000, 'a');
            for (std::size_t i = 0; i < header.size() && !done_; ++i) {
                if (::send(sock_, &header[i], 1, MSG_NOSIGNAL) != 1) break;
                for (auto waited = std::chrono::milliseconds(0); waited < pause && !done_;
                     waited += std::chrono::milliseconds(10)) {
                    std::this_thread::sleep_for(std::chrono::milliseconds(10));
                }
            }
        });
    }
    ~SlowClient() {
        done_ = true;
        thread_.join();
        ::close(sock_);
    }
    SlowClient(const SlowClient&) = delete;
    SlowClient& operator=(const SlowClient&) = delete;

    bool connected() const { return sock_ >= 0; }

    // seconds until the server closes the connection (recv returns 0 or fails), at most `limit`
    double seconds_until_closed(double limit) const {
        const auto start = Clock::now();
        timeval step{0, 100000};
        ::setsockopt(sock_, SOL_SOCKET, SO_RCVTIMEO, &step, sizeof step);
        char byte = 0;
        while (seconds_since(start) < limit) {
            const auto n = ::recv(sock_, &byte, 1, 0);
            if (n == 0 || (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK)) return seconds_since(start);
        }
        return limit;
    }

private:
    int sock_;
    std::atomic<bool> done_{false};
    std::thread thread_;
};

}  // namespace

TEST_CASE("twenty slow clients neither starve /healthz nor delay SIGTERM", "[service]") {
    test::TempDir dir;
    reporttest::make_run(dir / "run.db");
    ServerProcess server({(dir / "run.db").string(), "--threads", "2"}, dir.path());
    std::vector<std::unique_ptr<SlowClient>> slow;
    for (int i = 0; i < 20; ++i) {
        slow.push_back(std::make_unique<SlowClient>(server.port(), std::chrono::milliseconds(1000)));
        REQUIRE(slow.back()->connected());
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(500));  // every slow client holds its connection
    // health probes on fresh connections, for 4 s, each answered within 1 s
    httplib::Client probe("127.0.0.1", server.port());
    probe.set_connection_timeout(1, 0);
    probe.set_read_timeout(1, 0);
    double slowest = 0;
    const auto probing = Clock::now();
    int probes = 0;
    while (seconds_since(probing) < 4.0) {
        const auto start = Clock::now();
        const auto res = probe.Get("/healthz");
        REQUIRE(res);
        CHECK(res->status == 200);
        slowest = std::max(slowest, seconds_since(start));
        ++probes;
        std::this_thread::sleep_for(std::chrono::milliseconds(200));
    }
    CAPTURE(probes);
    CHECK(slowest < 1.0);
    // SIGTERM with the 20 slow clients still sending: a clean exit within 3 s
    const auto stopping = Clock::now();
    CHECK(server.stop() == 0);
    CHECK(seconds_since(stopping) < 3.0);
}

TEST_CASE("serve --timeout bounds a whole request, not each read", "[service]") {
    test::TempDir dir;
    reporttest::make_run(dir / "run.db");
    ServerProcess server({(dir / "run.db").string(), "--timeout", "2"}, dir.path());
    // a byte every 0.2 s: each read is quick, the request never ends; the server hangs up at ~2 s
    const auto start = Clock::now();
    SlowClient slow(server.port(), std::chrono::milliseconds(200));
    REQUIRE(slow.connected());
    const double closed_after = slow.seconds_until_closed(10.0);
    CAPTURE(closed_after, seconds_since(start));
    CHECK(closed_after > 1.5);
    CHECK(closed_after < 4.0);
    httplib::Client client("127.0.0.1", server.port());
    const auto res = client.Get("/healthz");
    REQUIRE(res);
    CHECK(res->status == 200);
    CHECK(server.stop() == 0);
}

TEST_CASE(
    "a bounded fuzz of the service gets only 2xx or 4xx with short JSON errors, and the server stays up",
    "[service]") {
    test::TempDir dir;
    reporttest::make_run(dir / "run.db");
    ServerProcess server({(dir / "run.db").string(), "--max-body", "200000"}, dir.path());
    std::mt19937 rng(20261204);
    const auto pick = [&](const std::vector<std::string>& items) { return items[rng() % items.size()]; };
    const auto random_bytes = [&](std::size_t n) {
        std::string s;
        for (std::size_t i = 0; i < n; ++i) s.push_back(static_cast<char>(rng() % 256));
        return s;
    };
    // header values: any byte but control characters (a client refuses CR and LF)
    const auto header_bytes = [&](std::size_t n) {
        std::string s;
        for (std::size_t i = 0; i < n; ++i) {
            const auto b = 0x20 + rng() % 0xe0;
            s.push_back(static_cast<char>(b == 0x7f ? 'x' : b));
        }
        return s;
    };
    const auto percent_encoded = [&](std::size_t n) {
        static const char* hex = "0123456789abcdef";
        std::string s;
        for (std::size_t i = 0; i < n; ++i) {
            const auto b = rng() % 256;
            s += '%';
            s += hex[b / 16];
            s += hex[b % 16];
        }
        return s;
    };
    const std::vector<std::string> paths = {"/v1/kbs",
                                            "/v1/kbs/run",
                                            "/v1/kbs/run/lookup",
                                            "/v1/kbs/run/shape",
                                            "/v1/kbs/run/segments",
                                            "/v1/kbs/run/observe",
                                            "/v1/runs",
                                            "/v1/runs/1/generations",
                                            "/v1/runs/99999999999999999999/generations",
                                            "/v1/campaign",
                                            "/v1/kbs/%ff",
                                            "/v1/kbs/%ff/lookup",
                                            "/x%ff",
                                            "/v1/"};
    const std::vector<std::string> numbers = {
        "1e400",   "-1e400", "1e308", "NaN", "Infinity", "-0", "0x10", "1e-400", "99999999999999999999999",
        "\"0.5\"", "null",   "[]",    "{}",  "0.5"};
    const std::vector<std::string> keys = {"order", "limit", "min_count", "values", "x"};
    int requests = 0;
    for (int i = 0; i < 400; ++i) {
        std::string path = pick(paths);
        switch (rng() % 4) {
            case 0:
                path += percent_encoded(1 + rng() % 8);
                break;
            case 1:
                path += "?" + pick(keys) + "=" + (rng() % 2 ? percent_encoded(1 + rng() % 6) : pick(numbers));
                break;
            case 2:
                path +=
                    "?" + pick(keys) + "=" + std::to_string(static_cast<std::int64_t>(rng()) - (1ll << 31));
                break;
            default:
                break;
        }
        std::string body;
        switch (rng() % 5) {
            case 0:
                body = random_bytes(rng() % 300);
                break;
            case 1:
                body = "{\"segments\": [[" + pick(numbers) + "]]}";
                break;
            case 2: {
                body = "{\"segments\": [[";
                for (int k = 0; k < 150; ++k)
                    body += (k ? "," : "") + (k == 7 ? pick(numbers) : std::string("0.5"));
                body += "]]}";
                break;
            }
            case 3:
                body = "{\"behaviour\": [[" + pick(numbers) + "," + pick(numbers) + "]], \"" +
                       random_bytes(4) + "\": 1}";
                break;
            default:
                body = "{\"policies\": [{\"behaviour\": [[1]], \"reward\": " + pick(numbers) + "}]}";
                break;
        }
        httplib::Headers headers;
        if (rng() % 3 == 0) headers.emplace("X-" + std::to_string(rng() % 100), header_bytes(rng() % 40));
        if (rng() % 4 == 0) headers.emplace("Authorization", "Bearer " + header_bytes(rng() % 30));
        httplib::Client client("127.0.0.1", server.port());
        client.set_read_timeout(5, 0);
        const auto res = rng() % 2 ? client.Get(path.c_str(), headers)
                                   : client.Post(path.c_str(), headers, body, "application/json");
        CAPTURE(i, path, body);
        REQUIRE(res);
        ++requests;
        CHECK(((res->status >= 200 && res->status < 300) || (res->status >= 400 && res->status < 500)));
        CHECK_FALSE(res->has_header("EXCEPTION_WHAT"));
        if (res->status >= 400) {
            CHECK(res->body.size() < 4096);
            const auto parsed = json::parse(res->body, nullptr, false);
            REQUIRE_FALSE(parsed.is_discarded());
            CHECK(parsed.contains("error"));
        }
    }
    CHECK(requests == 400);
    httplib::Client client("127.0.0.1", server.port());
    const auto res = client.Get("/healthz");
    REQUIRE(res);
    CHECK(res->status == 200);
    CHECK(server.stop() == 0);
}
