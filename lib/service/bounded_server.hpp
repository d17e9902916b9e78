#pragma once

// The service's HTTP/1.1 server: connections bounded in time and memory, on
// Boost.Beast's and Boost.Asio's public API only (no library's private or
// protected members, no subclass of a library class).
//
// How the guarantees are kept (docs/service.md, "How the bounds are kept"):
// - a whole-request deadline: one beast::tcp_stream expiry is set when a
//   request's first byte arrives and is not renewed until its answer's last
//   byte is written, so a client sending a byte a second is hung up on when
//   the request's time is up (Beast closes the socket and fails the read);
//   a kept-alive connection waits at most `idle_time` for its next request;
// - slow clients hold no thread: reads and writes are asynchronous on one
//   I/O thread, handlers run on `workers` threads, and the cheap routes
//   (/healthz, the page) are answered on the I/O thread at once;
// - stopping: the acceptor is closed, connections waiting for or receiving a
//   request are closed at once, handlers running finish, and every
//   connection still open `stop_grace` later is closed;
// - memory: a header is at most `max_header` bytes (Beast's header_limit), a
//   body at most `max_body` (refused from its Content-Length before it is
//   read, or Beast's body_limit for a chunked one), and bodies held at once,
//   from their header to their answer, at most `body_budget` bytes (503
//   beyond); the body is read into a string reserved to its length.
//
// cpp-httplib (0.11.4, Debian 12) has none of this through its public API: its
// timeouts are per read, its stop() waits for slow clients, a form-encoded
// body over 8 KiB is refused, and a POST without Content-Length waits for the
// client to close; the service's earlier subclass overrode a private member.

#include <chrono>
#include <cstddef>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace stepstone::service {

/// A request as a handler sees it.
struct HttpRequest {
    std::string method;                              ///< as sent: GET, POST
    std::string path;                                ///< percent-decoded, without the query
    std::multimap<std::string, std::string> params;  ///< the query's, decoded
    std::vector<std::string> matches;                ///< the route's groups; [0] is the whole path
    std::vector<std::pair<std::string, std::string>> headers;
    std::string body;  ///< a handler may release it once read

    bool has_param(const std::string& key) const { return params.count(key) > 0; }
    std::string get_param_value(const std::string& key) const;
    /// The first header of this name (any case), or "".
    std::string header(const std::string& name) const;
};

struct HttpResponse {
    int status = 200;
    std::string content_type = "application/json";
    std::string body;
};

using HttpHandler = std::function<void(HttpRequest&, HttpResponse&)>;
/// Fills `res` with an error answer of `status` naming the problem in `message`.
using HttpErrorWriter = std::function<void(HttpResponse& res, int status, const std::string& message)>;

struct ServerBounds {
    std::chrono::milliseconds request_time{30000};   ///< a request's first byte to its answer's last
    std::chrono::milliseconds idle_time{5000};       ///< a kept-alive connection's wait for its next request
    std::chrono::milliseconds stop_grace{1000};      ///< answers still being written when stopped
    std::size_t max_body = std::size_t{64} << 20;    ///< larger bodies get 413
    std::size_t max_header = std::size_t{16} << 10;  ///< request line and headers; larger get 431
    std::size_t body_budget = std::size_t{128} << 20;  ///< bodies held at once; more get 503
    unsigned connections = 64;                         ///< open at once; more wait to be accepted
    unsigned workers = 2;                              ///< handlers running at once
    unsigned requests_per_connection = 100;
};

class BoundedServer {
public:
    BoundedServer(const ServerBounds& bounds, HttpErrorWriter errors);
    ~BoundedServer();
    BoundedServer(const BoundedServer&) = delete;
    BoundedServer& operator=(const BoundedServer&) = delete;

    /// Answers `method` on paths matching the regex `pattern` whole. `on_io_thread`:
    /// a handler that does no work worth a thread (it must not block).
    void route(const std::string& method, const std::string& pattern, HttpHandler handler,
               bool on_io_thread = false);

    /// Binds `host` (a name or address) and `port` (0: any free port): the port, or -1.
    int bind(const std::string& host, int port);
    /// Serves until stop_all(); returns once every connection is closed and every handler has returned.
    void run();
    /// Stops accepting and ends every connection within stop_grace. Any thread, any time.
    void stop_all();

    /// Bytes of request bodies held now (tests and the memory bound).
    std::size_t held_body_bytes() const;

    struct Impl;  // opaque: Beast and Asio stay out of this header

private:
    std::shared_ptr<Impl> impl_;
};

}  // namespace stepstone::service
