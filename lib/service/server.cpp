// stepstone serve: the KB service over HTTP (cpp-httplib), until SIGINT or SIGTERM.

#include <httplib.h>
#include <signal.h>
#include <sys/socket.h>

#include <algorithm>
#include <atomic>
#include <charconv>
#include <fstream>
#include <iostream>
#include <semaphore>
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
void reply(httplib::Response& res, int status, const json& body) {
    res.status = status;
    res.set_content(body.dump(-1, ' ', false, json::error_handler_t::replace), "application/json");
}

// an error message echoes at most this many bytes of what the client sent
constexpr std::size_t kMaxMessage = 300;

void fail(httplib::Response& res, int status, const std::string& message) {
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

std::uint64_t parse_count(const httplib::Request& req, const char* key, std::uint64_t fallback) {
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

}  // namespace

struct HttpServer::Impl {
    explicit Impl(const ServeOptions& options)
        : token(checked_token(options)),
          server(request_time(options), kIdleTime),
          work_slots(work_threads(options)) {}
    std::string token;
    std::unique_ptr<KbService> service;
    BoundedServer server;
    // requests doing KB work at once (--threads); connections waiting on a
    // slow client hold none, and /healthz needs none
    std::counting_semaphore<> work_slots;
    int port = -1;
};

namespace {

// RAII: one of the work slots for the handler's time
class WorkSlot {
public:
    explicit WorkSlot(std::counting_semaphore<>& slots) : slots_(slots) { slots_.acquire(); }
    ~WorkSlot() { slots_.release(); }
    WorkSlot(const WorkSlot&) = delete;
    WorkSlot& operator=(const WorkSlot&) = delete;

private:
    std::counting_semaphore<>& slots_;
};

}  // namespace

HttpServer::HttpServer(const ServeOptions& options) : impl_(std::make_unique<Impl>(options)) {
    const std::string& token = impl_->token;
    impl_->service = std::make_unique<KbService>(options.input, options.writable, options.limits);
    KbService& service = *impl_->service;
    BoundedServer& server = impl_->server;
    // one thread a connection: a slow client holds its thread, at most --timeout
    const auto connections = options.connections;
    server.new_task_queue = [connections] { return new httplib::ThreadPool(connections); };
    server.set_keep_alive_max_count(100);
    server.set_payload_max_length(options.limits.max_body_bytes);
    // every /v1 request passes the token check, then the handler in a work slot; errors become JSON
    using Handler = std::function<void(const httplib::Request&, httplib::Response&)>;
    auto& slots = impl_->work_slots;
    const auto guarded = [&token, &slots](Handler handler) {
        return [handler, &token, &slots](const httplib::Request& req, httplib::Response& res) {
            try {
                if (!token.empty() && req.get_header_value("Authorization") != "Bearer " + token) {
                    throw HttpError(401, "missing or wrong bearer token (Authorization: Bearer <token>)");
                }
                const WorkSlot slot(slots);
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

    server.Get("/healthz", [](const httplib::Request&, httplib::Response& res) { reply(res, 200, {{"status", "ok"}}); });
    server.Get("/", [](const httplib::Request&, httplib::Response& res) {
        res.set_content(std::string(dashboard_html()), "text/html; charset=utf-8");
    });
    server.Get("/v1/kbs", guarded([&](const auto&, auto& res) { reply(res, 200, service.list_kbs()); }));
    server.Get(R"(/v1/kbs/([^/]+))",
               guarded([&](const auto& req, auto& res) { reply(res, 200, service.kb_info(req.matches[1])); }));
    server.Post(R"(/v1/kbs/([^/]+)/lookup)", guarded([&](const auto& req, auto& res) {
                    // the body's DOM is freed before the answer is written
                    const auto answer = service.lookup(req.matches[1], parse_body(req.body));
                    reply(res, 200, answer);
                }));
    server.Post(R"(/v1/kbs/([^/]+)/shape)", guarded([&](const auto& req, auto& res) {
                    const auto answer = service.shape(req.matches[1], parse_body(req.body));
                    reply(res, 200, answer);
                }));
    server.Get(R"(/v1/kbs/([^/]+)/segments)", guarded([&](const auto& req, auto& res) {
                   const auto order = req.has_param("order") ? req.get_param_value("order") : std::string("reward");
                   const auto values = req.has_param("values") && req.get_param_value("values") == "1";
                   reply(res, 200,
                         service.segments(req.matches[1], order, parse_count(req, "limit", 20),
                                          parse_count(req, "min_count", 1), values));
               }));
    server.Post(R"(/v1/kbs/([^/]+)/observe)", guarded([&](const auto& req, auto& res) {
                    const auto answer = service.observe(req.matches[1], parse_body(req.body));
                    reply(res, 200, answer);
                }));
    server.Get("/v1/runs", guarded([&](const auto&, auto& res) { reply(res, 200, service.runs()); }));
    server.Get(R"(/v1/runs/(\d+)/generations)", guarded([&](const auto& req, auto& res) {
                   const std::string id = req.matches[1];
                   // more digits than any run id has: no such run (std::stoll would throw)
                   if (id.size() > 18) throw HttpError(404, concat("no run ", id.substr(0, 40), " here"));
                   reply(res, 200, service.generations(std::stoll(id)));
               }));
    server.Get("/v1/campaign", guarded([&](const auto&, auto& res) { reply(res, 200, service.campaign()); }));
    server.set_error_handler([](const httplib::Request& req, httplib::Response& res) {
        // only statuses no handler set: unknown paths (404), bodies over the limit (413)
        if (!res.body.empty()) return;
        const std::string message = res.status == 404   ? concat("no such endpoint: ", req.method, " ", req.path)
                                    : res.status == 413 ? "the request body is too large"
                                                        : concat("HTTP ", res.status);
        fail(res, res.status, message);
    });
    // an exception no handler caught: a JSON 500 without the library's EXCEPTION_WHAT header
    server.set_exception_handler([](const httplib::Request&, httplib::Response& res, std::exception_ptr) {
        fail(res, 500, "internal error");
    });

    // answers leave at once on a reused connection (no Nagle wait for the client's delayed ACK)
    server.set_tcp_nodelay(true);
    // SO_REUSEADDR (a restart binds at once over connections in TIME_WAIT) but not the library's
    // default SO_REUSEPORT, with which a second server bound the same port and shared its requests
    server.set_socket_options([](socket_t sock) {
        int yes = 1;
        ::setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
    });

    int& port = impl_->port;
    port = options.port;
    if (port == 0) {
        port = server.bind_to_any_port(options.bind);
    } else if (!server.bind_to_port(options.bind, port)) {
        port = -1;
    }
    if (port < 0) throw Error(concat("cannot listen on ", options.bind, ":", options.port, " (in use, or not an address here)"));
}

HttpServer::~HttpServer() = default;

int HttpServer::port() const { return impl_->port; }

void HttpServer::run() { impl_->server.listen_after_bind(); }

void HttpServer::stop() { impl_->server.stop_all(); }

void serve(const ServeOptions& options) {
    // block the stop signals in every thread; one thread waits for them
    sigset_t stop_signals;
    sigemptyset(&stop_signals);
    sigaddset(&stop_signals, SIGINT);
    sigaddset(&stop_signals, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);

    HttpServer server(options);
    std::cout << "listening on http://" << options.bind << ":" << server.port()
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
