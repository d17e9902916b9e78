// stepstone serve: the KB service over HTTP (service/bounded_server.hpp), until SIGINT or SIGTERM.

#include <malloc.h>
#include <pthread.h>
#include <signal.h>

#include <algorithm>
#include <atomic>
#include <charconv>
#include <fstream>
#include <iostream>
#include <thread>

#include "core/embedded.hpp"
#include "core/error.hpp"
#include "core/text.hpp"
#include "service/body.hpp"
#include "service/bounded_server.hpp"
#include "service/service.hpp"

namespace stepstone {
std::span<const EmbeddedFile> dashboard_files();
}

namespace stepstone::service {

namespace {

using nlohmann::json;

// invalid UTF-8 (a path with %ff, say) is replaced by U+FFFD rather than thrown
void reply(HttpResponse& res, int status, const json& body) {
    res.status = status;
    res.content_type = "application/json";
    res.body = body.dump(-1, ' ', false, json::error_handler_t::replace);
}

// an error message echoes at most this many bytes of what the client sent
constexpr std::size_t kMaxMessage = 300;

void fail(HttpResponse& res, int status, const std::string& message) {
    const std::string bounded =
        message.size() <= kMaxMessage ? message : message.substr(0, kMaxMessage) + "... (message cut)";
    reply(res, status, {{"error", bounded}, {"status", status}});
}

std::string read_token(const std::filesystem::path& path) {
    std::ifstream in(path);
    if (!in) throw ConfigError(concat(option_name("token_file"), " ", path.string(), ": cannot be read"));
    std::string token;
    std::getline(in, token);
    while (!token.empty() && std::isspace(static_cast<unsigned char>(token.back()))) token.pop_back();
    if (token.size() < 16)
        throw ConfigError(concat(option_name("token_file"), " ", path.string(),
                                 ": the token must have at least 16 characters"));
    return token;
}

std::uint64_t parse_count(const HttpRequest& req, const char* key, std::uint64_t fallback) {
    if (!req.has_param(key)) return fallback;
    const auto text = req.get_param_value(key);
    std::uint64_t value = 0;
    const auto parsed = std::from_chars(text.data(), text.data() + text.size(), value);
    if (text.empty() || parsed.ec != std::errc() || parsed.ptr != text.data() + text.size()) {
        throw HttpError(400, concat(key, " must be a whole number >= 0, got \"", text, '"'));
    }
    return value;
}

}  // namespace

bool is_loopback(const std::string& host) {
    return host == "localhost" || host == "::1" || host.rfind("127.", 0) == 0;
}

std::string_view dashboard_html() {
    for (const auto& file : dashboard_files()) {
        if (file.path == "dashboard.html") return file.text;
    }
    return "<!DOCTYPE html><title>stepstone</title><p>dashboard missing from this build</p>";
}

namespace {

unsigned work_threads(const ServeOptions& options) {
    return options.threads > 0 ? options.threads : std::max(2u, std::thread::hardware_concurrency());
}

// the options' checks, before anything is opened or bound
void check_options(const ServeOptions& options, const std::string& token) {
    if (token.empty() && !is_loopback(options.bind)) {
        throw ConfigError(concat(option_name("bind"), " ", options.bind, " is not loopback: give ",
                                 option_name("token_file"),
                                 " so that only clients "
                                 "with the token are answered"));
    }
    if (token.empty() && options.writable)
        throw ConfigError(concat(option_name("writable"), " needs ", option_name("token_file"),
                                 " (writes need the token)"));
    if (options.port < 0 || options.port > 65535)
        throw ConfigError(concat(option_name("port"), " must be within 0 to 65535, got ", options.port));
    if (!(options.timeout_seconds >= 1 && options.timeout_seconds <= 3600)) {
        throw ConfigError(concat(option_name("timeout_seconds"), " must be within 1 to 3600 seconds, got ",
                                 shortest(options.timeout_seconds)));
    }
    if (options.threads > 1024)
        throw ConfigError(concat(option_name("threads"), " must be within 1 to 1024, got ", options.threads));
    if (options.connections < 1 || options.connections > 4096)
        throw ConfigError(
            concat(option_name("connections"), " must be within 1 to 4096, got ", options.connections));
    if (options.limits.max_body_bytes < 1 || options.limits.max_body_bytes > kMaxBodyLimit) {
        throw ConfigError(concat(option_name("max_body"), " must be within 1 to ", kMaxBodyLimit,
                                 " bytes, got ", options.limits.max_body_bytes));
    }
}

// the token of --token-file, once every option is checked (before anything is opened or bound)
std::string checked_token(const ServeOptions& options) {
    const std::string token = options.token_file.empty() ? std::string() : read_token(options.token_file);
    check_options(options, token);
    return token;
}

std::chrono::milliseconds request_time(const ServeOptions& options) {
    return std::chrono::milliseconds(static_cast<std::int64_t>(options.timeout_seconds * 1000.0));
}

// a kept-alive connection waits this long at most for its next request
constexpr std::chrono::milliseconds kIdleTime{5000};

ServerBounds bounds(const ServeOptions& options) {
    ServerBounds out;
    out.request_time = request_time(options);
    out.idle_time = kIdleTime;
    out.max_body = options.limits.max_body_bytes;
    // two bodies of the largest size received or worked on at once; more wait for a 503's retry
    out.body_budget = kBodiesAtOnce * options.limits.max_body_bytes;
    out.connections = options.connections;
    out.workers = work_threads(options);
    return out;
}

}  // namespace

struct HttpServer::Impl {
    explicit Impl(const ServeOptions& options)
        : token(checked_token(options)),
          server(bounds(options), [](HttpResponse& res, int status, const std::string& message) {
              fail(res, status, message);
          }) {}
    std::string token;
    std::unique_ptr<KbService> service;
    BoundedServer server;
    int port = -1;
};

namespace {

// a handler's body, parsed, then released: the DOM alone stays while the answer is computed
json take_body(HttpRequest& req) {
    auto parsed = parse_body(req.body);
    std::string().swap(req.body);
    return parsed;
}

}  // namespace

HttpServer::HttpServer(const ServeOptions& options) : impl_(std::make_unique<Impl>(options)) {
    const std::string& token = impl_->token;
    impl_->service = std::make_unique<KbService>(options.input, options.writable, options.limits);
    KbService& service = *impl_->service;
    BoundedServer& server = impl_->server;
    // every /v1 request passes the token check, then the handler on a worker; errors become JSON
    const auto guarded = [&token](HttpHandler handler) {
        return [handler, &token](HttpRequest& req, HttpResponse& res) {
            try {
                if (!token.empty() && req.header("Authorization") != "Bearer " + token) {
                    throw HttpError(401, "missing or wrong bearer token (Authorization: Bearer <token>)");
                }
                handler(req, res);
            } catch (const HttpError& e) {
                fail(res, e.status(), e.what());
            } catch (const Error& e) {
                fail(res, 400, e.what());
            } catch (const std::exception& e) {
                fail(res, 500, concat("internal error: ", e.what()));
            }
        };
    };

    // answered on the I/O thread: no work slot, never behind slow clients or long lookups
    server.route(
        "GET", "/healthz",
        [](HttpRequest&, HttpResponse& res) {
            reply(res, 200, {{"status", "ok"}});
        },
        true);
    server.route(
        "GET", "/",
        [](HttpRequest&, HttpResponse& res) {
            res.content_type = "text/html; charset=utf-8";
            res.body = std::string(dashboard_html());
        },
        true);
    server.route("GET", "/v1/kbs", guarded([&](auto&, auto& res) { reply(res, 200, service.list_kbs()); }));
    server.route("GET", R"(/v1/kbs/([^/]+))",
                 guarded([&](auto& req, auto& res) { reply(res, 200, service.kb_info(req.matches[1])); }));
    server.route("POST", R"(/v1/kbs/([^/]+)/lookup)", guarded([&](auto& req, auto& res) {
                     reply(res, 200, service.lookup(req.matches[1], take_body(req)));
                 }));
    server.route("POST", R"(/v1/kbs/([^/]+)/shape)", guarded([&](auto& req, auto& res) {
                     reply(res, 200, service.shape(req.matches[1], take_body(req)));
                 }));
    server.route("GET", R"(/v1/kbs/([^/]+)/segments)", guarded([&](auto& req, auto& res) {
                     const auto order =
                         req.has_param("order") ? req.get_param_value("order") : std::string("reward");
                     const auto values = req.has_param("values") && req.get_param_value("values") == "1";
                     reply(res, 200,
                           service.segments(req.matches[1], order, parse_count(req, "limit", 20),
                                            parse_count(req, "min_count", 1), values));
                 }));
    server.route("POST", R"(/v1/kbs/([^/]+)/observe)", guarded([&](auto& req, auto& res) {
                     reply(res, 200, service.observe(req.matches[1], take_body(req)));
                 }));
    server.route("GET", "/v1/runs", guarded([&](auto&, auto& res) { reply(res, 200, service.runs()); }));
    server.route("GET", R"(/v1/runs/(\d+)/generations)", guarded([&](auto& req, auto& res) {
                     const std::string id = req.matches[1];
                     // more digits than any run id has: no such run (std::stoll would throw)
                     if (id.size() > 18) throw HttpError(404, concat("no run ", id.substr(0, 40), " here"));
                     reply(res, 200, service.generations(std::stoll(id)));
                 }));
    server.route("GET", "/v1/campaign",
                 guarded([&](auto&, auto& res) { reply(res, 200, service.campaign()); }));

    int& port = impl_->port;
    port = server.bind(options.bind, options.port);
    if (port < 0) {
        throw Error(concat("cannot listen on ", options.bind, ":", options.port,
                           " (in use, or not an address here)"));
    }
}

HttpServer::~HttpServer() = default;

int HttpServer::port() const { return impl_->port; }

void HttpServer::run() { impl_->server.run(); }

void HttpServer::stop() { impl_->server.stop_all(); }

std::string url_of(const std::string& host, int port) {
    // an IPv6 address is bracketed in a URL (RFC 3986): http://[::1]:8080
    const bool v6 = host.find(':') != std::string::npos;
    return concat("http://", v6 ? "[" : "", host, v6 ? "]" : "", ":", port);
}

void serve(const ServeOptions& options) {
    // block the stop signals in every thread; one thread waits for them
    sigset_t stop_signals;
    sigemptyset(&stop_signals);
    sigaddset(&stop_signals, SIGINT);
    sigaddset(&stop_signals, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);

    // memory given back (docs/service.md, "Memory"): buffers of 1 MiB and more are mapped apart and
    // unmapped when freed (a fixed threshold: glibc's sliding one kept a 32 MiB body's pages in the heap),
    // and the threads share two arenas rather than one each
    ::mallopt(M_MMAP_THRESHOLD, 1 << 20);
    ::mallopt(M_ARENA_MAX, 2);
    HttpServer server(options);
    std::cout << "listening on " << url_of(options.bind, server.port())
              << (options.writable ? " (writable)" : " (read-only)") << std::endl;
    std::atomic<bool> signalled{false};
    std::thread stopper([&] {
        int signal = 0;
        sigwait(&stop_signals, &signal);
        signalled = true;
        server.stop();
    });
    server.run();
    // run returns after stop(): the thread pool joined, every request answered;
    // if it ended for another reason, wake the waiting thread
    if (!signalled) pthread_kill(stopper.native_handle(), SIGTERM);
    stopper.join();
    std::cerr << "stepstone serve: stopped; every observation answered is committed" << std::endl;
}

}  // namespace stepstone::service
