// BoundedServer: httplib's request handling over a socket stream with a deadline.

#include "service/bounded_server.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>

namespace stepstone::service {

namespace {

using Clock = std::chrono::steady_clock;
using std::chrono::milliseconds;

// how often a waiting connection looks at the stop flag
constexpr milliseconds kSlice{50};

void address_of(const sockaddr_storage& address, std::string& ip, int& port) {
    char text[INET6_ADDRSTRLEN] = {};
    if (address.ss_family == AF_INET) {
        const auto& a = reinterpret_cast<const sockaddr_in&>(address);
        ::inet_ntop(AF_INET, &a.sin_addr, text, sizeof text);
        port = ntohs(a.sin_port);
    } else if (address.ss_family == AF_INET6) {
        const auto& a = reinterpret_cast<const sockaddr_in6&>(address);
        ::inet_ntop(AF_INET6, &a.sin6_addr, text, sizeof text);
        port = ntohs(a.sin6_port);
    }
    ip = text;
}

// A connection's socket: reads are buffered (httplib reads request lines a
// byte at a time), and every read or write waits at most until the deadline.
class DeadlineStream final : public httplib::Stream {
public:
    DeadlineStream(socket_t sock, const BoundedServer::StopState& stop) : sock_(sock), stop_(stop) {}

    void set_deadline(Clock::time_point deadline) { deadline_ = deadline; }

    bool is_readable() const override { return begin_ < end_ || wait(POLLIN); }
    bool is_writable() const override { return wait(POLLOUT); }

    ssize_t read(char* ptr, size_t size) override {
        if (begin_ == end_) {
            if (!wait(POLLIN)) return -1;
            ssize_t n = 0;
            do {
                n = ::recv(sock_, buffer_.data(), buffer_.size(), 0);
            } while (n < 0 && errno == EINTR);
            if (n <= 0) return n;
            begin_ = 0;
            end_ = static_cast<std::size_t>(n);
        }
        const auto n = std::min(size, end_ - begin_);
        std::memcpy(ptr, buffer_.data() + begin_, n);
        begin_ += n;
        return static_cast<ssize_t>(n);
    }

    ssize_t write(const char* ptr, size_t size) override {
        if (!wait(POLLOUT)) return -1;
        ssize_t n = 0;
        do {
            n = ::send(sock_, ptr, size, MSG_NOSIGNAL);
        } while (n < 0 && errno == EINTR);
        return n;
    }

    void get_remote_ip_and_port(std::string& ip, int& port) const override {
        sockaddr_storage address{};
        socklen_t length = sizeof address;
        if (::getpeername(sock_, reinterpret_cast<sockaddr*>(&address), &length) == 0)
            address_of(address, ip, port);
    }

    void get_local_ip_and_port(std::string& ip, int& port) const override {
        sockaddr_storage address{};
        socklen_t length = sizeof address;
        if (::getsockname(sock_, reinterpret_cast<sockaddr*>(&address), &length) == 0)
            address_of(address, ip, port);
    }

    socket_t socket() const override { return sock_; }

private:
    // true once `events` (or the peer's hang-up) is ready; false at the
    // deadline, at once for a read when the server stops, and for a write
    // after the stop's grace
    bool wait(short events) const {
        for (;;) {
            auto limit = deadline_;
            if (stop_.stopping.load()) {
                if (events == POLLIN) return false;
                limit = std::min(limit, Clock::time_point(Clock::duration(stop_.since.load())) +
                                            BoundedServer::kStopGrace);
            }
            const auto now = Clock::now();
            if (now >= limit) return false;
            const auto slice = std::min<Clock::duration>(limit - now, kSlice);
            pollfd fd{sock_, events, 0};
            const int ready =
                ::poll(&fd, 1, static_cast<int>(std::chrono::ceil<milliseconds>(slice).count()));
            if (ready > 0) return true;  // readable, writable, or hung up: recv/send say which
            if (ready < 0 && errno != EINTR) return false;
        }
    }

    socket_t sock_;
    const BoundedServer::StopState& stop_;
    Clock::time_point deadline_ = Clock::now();
    std::array<char, 4096> buffer_{};
    std::size_t begin_ = 0, end_ = 0;
};

}  // namespace

BoundedServer::BoundedServer(milliseconds request_time, milliseconds idle_time)
    : request_time_(request_time), idle_time_(idle_time) {}

void BoundedServer::stop_all() {
    stop_.since = Clock::now().time_since_epoch().count();
    stop_.stopping = true;
    stop();
}

bool BoundedServer::process_and_close_socket(socket_t sock) {
    DeadlineStream stream(sock, stop_);
    bool ok = false;
    for (std::size_t left = keep_alive_max_count_; left > 0 && !stop_.stopping; --left) {
        // the next request's first byte, within the idle time
        stream.set_deadline(Clock::now() + idle_time_);
        if (!stream.is_readable()) break;
        stream.set_deadline(Clock::now() + request_time_);
        bool closed = false;
        ok = process_request(stream, left == 1 || stop_.stopping, closed, nullptr);
        if (!ok || closed) break;
    }
    ::shutdown(sock, SHUT_RDWR);
    ::close(sock);
    return ok;
}

}  // namespace stepstone::service
