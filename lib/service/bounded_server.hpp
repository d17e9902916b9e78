#pragma once

// An httplib::Server whose connections are bounded in time, so that slow or
// stalled clients cannot hold the service: each request must arrive and be
// answered within its deadline, a kept-alive connection waits a bounded time
// for its next request, and stop_all() ends every connection within about a
// second whatever the clients do.

#include <httplib.h>

#include <atomic>
#include <chrono>

namespace stepstone::service {

class BoundedServer : public httplib::Server {
public:
    /// `request_time`: from a request's first byte to its answer's last byte.
    /// `idle_time`: how long a kept-alive connection may wait for its next request.
    BoundedServer(std::chrono::milliseconds request_time, std::chrono::milliseconds idle_time);

    /// Stops accepting and ends every connection: reads give up at once,
    /// answers being written get at most kStopGrace more. Any thread.
    void stop_all();

    static constexpr std::chrono::milliseconds kStopGrace{1000};

    /// What a connection's stream reads of the server: whether it stops, and since when.
    struct StopState {
        std::atomic<bool> stopping{false};
        std::atomic<std::chrono::steady_clock::rep> since{0};
    };

private:
    // replaces the library's connection loop (keep-alive, per-read timeouts)
    // with one under the request deadline; httplib's request parsing and
    // routing (process_request) are kept
    bool process_and_close_socket(socket_t sock) override;

    std::chrono::milliseconds request_time_, idle_time_;
    StopState stop_;
};

}  // namespace stepstone::service
