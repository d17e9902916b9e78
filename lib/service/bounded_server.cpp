// BoundedServer: HTTP/1.1 on Boost.Beast with a deadline per request (bounded_server.hpp).

#include "service/bounded_server.hpp"

#include <malloc.h>

#include <array>
#include <atomic>
#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <cctype>
#include <list>
#include <optional>
#include <regex>
#include <string_view>

#include "core/text.hpp"

namespace stepstone::service {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
using tcp = asio::ip::tcp;

namespace {

// a request or answer this large gives its memory back to the system once answered
constexpr std::size_t kLarge = std::size_t{1} << 20;
// how long a refused request's unread body is read and dropped before the connection is closed,
// so that the client reads the refusal rather than a reset
constexpr std::chrono::seconds kLinger{2};

int hex_digit(char c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
}

// %XX decoded (a malformed escape is kept as sent); '+' is a space in a query
std::string decode(std::string_view text, bool plus_is_space) {
    std::string out;
    out.reserve(text.size());
    for (std::size_t i = 0; i < text.size(); ++i) {
        if (text[i] == '%' && i + 2 < text.size() && hex_digit(text[i + 1]) >= 0 &&
            hex_digit(text[i + 2]) >= 0) {
            out.push_back(static_cast<char>(hex_digit(text[i + 1]) * 16 + hex_digit(text[i + 2])));
            i += 2;
        } else if (plus_is_space && text[i] == '+') {
            out.push_back(' ');
        } else {
            out.push_back(text[i]);
        }
    }
    return out;
}

bool same_letters(std::string_view a, std::string_view b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i) {
        if (std::tolower(static_cast<unsigned char>(a[i])) != std::tolower(static_cast<unsigned char>(b[i])))
            return false;
    }
    return true;
}

}  // namespace

std::string HttpRequest::get_param_value(const std::string& key) const {
    const auto it = params.find(key);
    return it == params.end() ? std::string() : it->second;
}

std::string HttpRequest::header(const std::string& name) const {
    for (const auto& [key, value] : headers) {
        if (same_letters(key, name)) return value;
    }
    return {};
}

namespace {

struct Route {
    std::string method;
    std::regex pattern;
    HttpHandler handler;
    bool on_io_thread;
};

class Connection;

}  // namespace

struct BoundedServer::Impl {
    Impl(const ServerBounds& b, HttpErrorWriter e) : bounds(b), errors(std::move(e)), workers(b.workers) {}
    ~Impl() {
        stopping = true;
        workers.join();
    }

    void accept();
    void begin_stop();
    void watch_stop();
    bool reserve(std::size_t bytes) {
        if (held.fetch_add(bytes) + bytes <= bounds.body_budget) return true;
        held -= bytes;
        return false;
    }
    void release(std::size_t bytes) { held -= bytes; }
    void answer(const Route& route, HttpRequest& req, HttpResponse& res) const {
        try {
            route.handler(req, res);
        } catch (...) {
            res = {};
            errors(res, 500, "internal error");
        }
    }

    ServerBounds bounds;
    HttpErrorWriter errors;
    std::vector<Route> routes;
    std::atomic<bool> stopping{false};
    std::atomic<std::size_t> held{0};
    std::atomic<unsigned> open{0};
    // the I/O thread's alone
    bool accepting = false;
    std::list<std::weak_ptr<Connection>> live;
    asio::io_context io{1};
    tcp::acceptor acceptor{io};
    asio::steady_timer retry{io}, grace{io};
    std::chrono::steady_clock::time_point stop_since;
    asio::thread_pool workers;
};

namespace {

class Connection : public std::enable_shared_from_this<Connection> {
public:
    Connection(BoundedServer::Impl& server, tcp::socket socket)
        : server_(server), stream_(std::move(socket)), buffer_(server.bounds.max_header + 65536) {
        ++server_.open;
    }
    ~Connection() {
        if (held_) server_.release(held_);
        --server_.open;
        if (!server_.stopping) asio::post(server_.io, [&server = server_] { server.accept(); });
    }
    Connection(const Connection&) = delete;
    Connection& operator=(const Connection&) = delete;

    void start() { wait_for_request(); }

    // stopping: a connection waiting for or receiving a request is closed now; one whose
    // handler runs or whose answer is being written is left to the grace timer
    void on_stop() {
        if (phase_ != Phase::working && phase_ != Phase::writing) close();
    }

    void close() {
        phase_ = Phase::closed;
        beast::error_code ignored;
        stream_.socket().shutdown(tcp::socket::shutdown_both, ignored);
        stream_.close();
    }

private:
    enum class Phase { idle, reading, working, writing, closed };

    void wait_for_request() {
        if (server_.stopping) return close();
        phase_ = Phase::idle;
        if (buffer_.size() > 0) return read_header();  // a request sent before the last answer
        stream_.expires_after(server_.bounds.idle_time);
        stream_.async_read_some(buffer_.prepare(4096),
                                [self = shared_from_this()](beast::error_code ec, std::size_t n) {
                                    if (ec) return self->close();
                                    self->buffer_.commit(n);
                                    self->read_header();
                                });
    }

    // from the request's first byte (in buffer_) to its answer's last: one deadline
    void read_header() {
        phase_ = Phase::reading;
        stream_.expires_after(server_.bounds.request_time);
        parser_.emplace();
        parser_->header_limit(static_cast<std::uint32_t>(server_.bounds.max_header));
        parser_->body_limit(server_.bounds.max_body);
        http::async_read_header(
            stream_, buffer_, *parser_,
            [self = shared_from_this()](beast::error_code ec, std::size_t) { self->on_header(ec); });
    }

    void on_header(beast::error_code ec) {
        // a Content-Length over max_body: Beast's parser refuses it with the header
        if (ec == http::error::body_limit) return refuse(413, "the request body is too large", true);
        if (ec == http::error::header_limit) {
            return refuse(
                431, concat("the request header is larger than ", server_.bounds.max_header, " bytes"), true);
        }
        // the client left, its time ran out, the server stops: no answer
        if (ec == http::error::end_of_stream || ec == http::error::partial_message ||
            phase_ == Phase::closed ||
            (ec && ec.category() != http::make_error_code(http::error::bad_target).category())) {
            return close();
        }
        if (ec) return refuse(400, concat("malformed HTTP request: ", ec.message()), true);
        const auto& head = parser_->get();
        version_ = head.version();
        keep_alive_ = parser_->keep_alive();
        request_ = HttpRequest{};
        request_.method = std::string(head.method_string());
        const std::string_view target(head.target().data(), head.target().size());
        const auto question = target.find('?');
        request_.path = decode(target.substr(0, question), false);
        if (question != std::string_view::npos) {
            std::string_view query = target.substr(question + 1);
            while (!query.empty()) {
                const auto amp = query.find('&');
                const auto pair = query.substr(0, amp);
                const auto eq = pair.find('=');
                if (!pair.empty()) {
                    request_.params.emplace(
                        decode(pair.substr(0, eq), true),
                        eq == std::string_view::npos ? std::string() : decode(pair.substr(eq + 1), true));
                }
                query = amp == std::string_view::npos ? std::string_view() : query.substr(amp + 1);
            }
        }
        for (const auto& field : head) {
            request_.headers.emplace_back(std::string(field.name_string()), std::string(field.value()));
        }
        route_ = nullptr;
        // HEAD is GET without the body
        head_ = request_.method == "HEAD";
        const std::string method = head_ ? std::string("GET") : request_.method;
        for (const auto& route : server_.routes) {
            std::smatch match;
            if (route.method == method && std::regex_match(request_.path, match, route.pattern)) {
                for (const auto& group : match) request_.matches.push_back(group.str());
                route_ = &route;
                break;
            }
        }
        const bool has_body = parser_->chunked() || parser_->content_length().value_or(0) > 0;
        const std::string what = concat(request_.method, " ", request_.path);
        if (!route_) return refuse(404, "no such endpoint: " + what, has_body);
        if (request_.method == "POST" && !has_body) {
            return refuse(
                400, concat("the request has no body: ", what, " takes a JSON body (and its Content-Length)"),
                false);
        }
        if (!has_body) return dispatch();
        const auto length = parser_->content_length();
        if (length && *length > server_.bounds.max_body)
            return refuse(413, "the request body is too large", true);
        const std::size_t need = length ? static_cast<std::size_t>(*length) : server_.bounds.max_body;
        if (!server_.reserve(need)) {
            return refuse(
                503,
                concat("the server holds ", server_.held.load(), " bytes of request bodies (at most ",
                       server_.bounds.body_budget, " at once): retry later"),
                true);
        }
        held_ = need;
        if (!same_letters(request_.header("Expect"), "100-continue")) return read_body();
        continue_ = {http::status::continue_, version_};
        http::async_write(stream_, continue_,
                          [self = shared_from_this()](beast::error_code error, std::size_t) {
                              if (error) return self->close();
                              self->read_body();
                          });
    }

    void read_body() {
        http::async_read(stream_, buffer_, *parser_,
                         [self = shared_from_this()](beast::error_code ec, std::size_t) {
                             if (ec == http::error::body_limit)
                                 return self->refuse(413, "the request body is too large", true);
                             if (ec) return self->close();
                             self->request_.body = std::move(self->parser_->get().body());
                             self->parser_.reset();
                             self->large_ = self->request_.body.size() >= kLarge;
                             self->dispatch();
                         });
    }

    void dispatch() {
        if (route_->on_io_thread) {
            HttpResponse res;
            server_.answer(*route_, request_, res);
            return respond(std::move(res), false);
        }
        phase_ = Phase::working;
        // the handler on a worker; the answer back on the I/O thread, which the work guard keeps running
        asio::post(server_.workers,
                   [self = shared_from_this(), guard = asio::make_work_guard(server_.io)]() mutable {
                       HttpResponse res;
                       self->server_.answer(*self->route_, self->request_, res);
                       auto& io = self->server_.io;
                       asio::post(io, [self = std::move(self), res = std::move(res)]() mutable {
                           self->respond(std::move(res), false);
                       });
                   });
    }

    // an error answer; `body_unread`: the connection is closed after it (its body is dropped)
    void refuse(int status, const std::string& message, bool body_unread) {
        HttpResponse res;
        server_.errors(res, status, message);
        respond(std::move(res), body_unread);
    }

    void respond(HttpResponse res, bool close_after) {
        if (phase_ == Phase::closed) return finish();  // closed by a stop meanwhile
        const bool keep = !close_after && keep_alive_ && !server_.stopping &&
                          ++served_ < server_.bounds.requests_per_connection;
        answer_ = {};
        answer_.version(version_);
        answer_.result(static_cast<unsigned>(res.status));
        answer_.set(http::field::content_type, res.content_type);
        answer_.body() = std::move(res.body);
        answer_.keep_alive(keep);
        answer_.prepare_payload();
        if (head_) {
            const auto length = answer_.body().size();
            answer_.body().clear();
            answer_.content_length(length);
        }
        large_ = large_ || answer_.body().size() >= kLarge;
        phase_ = Phase::writing;
        http::async_write(stream_, answer_,
                          [self = shared_from_this(), keep, close_after](beast::error_code ec, std::size_t) {
                              self->finish();
                              if (ec) return self->close();
                              if (close_after) return self->linger();
                              if (!keep) return self->close();
                              self->wait_for_request();
                          });
    }

    // the request's memory and its share of the body budget given back
    void finish() {
        if (held_) server_.release(held_);
        held_ = 0;
        request_ = HttpRequest{};
        answer_ = {};
        parser_.reset();
        if (large_) asio::post(server_.workers, [] { ::malloc_trim(0); });
        large_ = false;
    }

    // the answer is sent: read and drop what the client still sends, then close
    void linger() {
        phase_ = Phase::closed;
        beast::error_code ignored;
        stream_.socket().shutdown(tcp::socket::shutdown_send, ignored);
        stream_.expires_after(kLinger);
        drain();
    }

    void drain() {
        stream_.async_read_some(asio::buffer(discard_),
                                [self = shared_from_this()](beast::error_code ec, std::size_t) {
                                    if (ec) return self->close();
                                    self->drain();
                                });
    }

    BoundedServer::Impl& server_;
    beast::tcp_stream stream_;
    beast::flat_buffer buffer_;
    std::optional<http::request_parser<http::string_body>> parser_;
    http::response<http::empty_body> continue_;
    http::response<http::string_body> answer_;
    HttpRequest request_;
    const Route* route_ = nullptr;
    unsigned version_ = 11;
    bool keep_alive_ = false, large_ = false, head_ = false;
    std::size_t held_ = 0;
    unsigned served_ = 0;
    Phase phase_ = Phase::idle;
    std::array<char, 4096> discard_{};
};

}  // namespace

void BoundedServer::Impl::accept() {
    if (stopping || accepting || !acceptor.is_open() || open >= bounds.connections) return;
    accepting = true;
    acceptor.async_accept(io, [this](beast::error_code ec, tcp::socket socket) {
        accepting = false;
        if (stopping || ec == asio::error::operation_aborted) return;
        if (ec) {
            // out of descriptors and the like: try again shortly
            retry.expires_after(std::chrono::milliseconds(50));
            retry.async_wait([this](beast::error_code error) {
                if (!error) accept();
            });
            return;
        }
        beast::error_code ignored;
        // answers leave at once on a reused connection (no wait for the client's delayed ACK)
        socket.set_option(tcp::no_delay(true), ignored);
        auto connection = std::make_shared<Connection>(*this, std::move(socket));
        live.remove_if([](const auto& weak) { return weak.expired(); });
        live.push_back(connection);
        connection->start();
        accept();
    });
}

void BoundedServer::Impl::begin_stop() {
    if (stopping.exchange(true)) return;
    beast::error_code ignored;
    acceptor.close(ignored);
    retry.cancel();
    for (const auto& weak : live) {
        if (const auto connection = weak.lock()) connection->on_stop();
    }
    stop_since = std::chrono::steady_clock::now();
    watch_stop();
}

// run() returns once no connection is left: looked at every 50 ms, and what is still open after
// the grace (an answer still being written, a handler still running) is closed
void BoundedServer::Impl::watch_stop() {
    const bool late = std::chrono::steady_clock::now() - stop_since >= bounds.stop_grace;
    bool left = false;
    for (const auto& weak : live) {
        if (const auto connection = weak.lock()) {
            if (late) connection->close();
            left = true;
        }
    }
    if (!left) return;
    grace.expires_after(std::chrono::milliseconds(50));
    grace.async_wait([this](beast::error_code ec) {
        if (!ec) watch_stop();
    });
}

BoundedServer::BoundedServer(const ServerBounds& bounds, HttpErrorWriter errors)
    : impl_(std::make_shared<Impl>(bounds, std::move(errors))) {}

BoundedServer::~BoundedServer() = default;

void BoundedServer::route(const std::string& method, const std::string& pattern, HttpHandler handler,
                          bool on_io_thread) {
    impl_->routes.push_back({method, std::regex(pattern), std::move(handler), on_io_thread});
}

int BoundedServer::bind(const std::string& host, int port) {
    beast::error_code ec;
    tcp::resolver resolver(impl_->io);
    const auto endpoints = resolver.resolve(host, std::to_string(port),
                                            tcp::resolver::passive | tcp::resolver::numeric_service, ec);
    if (ec) return -1;
    for (const auto& entry : endpoints) {
        auto& acceptor = impl_->acceptor;
        beast::error_code error;
        acceptor.open(entry.endpoint().protocol(), error);
        // SO_REUSEADDR: a restart binds at once over connections in TIME_WAIT; not SO_REUSEPORT, with
        // which a second server bound the same port and shared its requests
        if (!error) acceptor.set_option(tcp::acceptor::reuse_address(true), error);
        if (!error) acceptor.bind(entry.endpoint(), error);
        if (!error) acceptor.listen(asio::socket_base::max_listen_connections, error);
        if (!error) return acceptor.local_endpoint().port();
        beast::error_code ignored;
        acceptor.close(ignored);
    }
    return -1;
}

void BoundedServer::run() {
    asio::post(impl_->io, [impl = impl_.get()] { impl->accept(); });
    impl_->io.run();
}

void BoundedServer::stop_all() {
    asio::post(impl_->io, [impl = impl_.get()] { impl->begin_stop(); });
}

std::size_t BoundedServer::held_body_bytes() const { return impl_->held.load(); }

}  // namespace stepstone::service
