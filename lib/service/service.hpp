#pragma once

#include <chrono>
#include <cstddef>
#include <filesystem>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <shared_mutex>
#include <stdexcept>
#include <string>
#include <vector>

namespace stepstone::service {

/// A request the service refuses: an HTTP status (4xx) and a one-line reason.
class HttpError : public std::runtime_error {
public:
    HttpError(int status, const std::string& message) : std::runtime_error(message), status_(status) {}
    int status() const { return status_; }

private:
    int status_;
};

/// The largest --max-body: 1 GiB (a request's memory is a few times its body, docs/service.md).
inline constexpr std::size_t kMaxBodyLimit = std::size_t{1} << 30;
/// Bodies of --max-body bytes that the server receives or works on at once; more get 503.
inline constexpr std::size_t kBodiesAtOnce = 2;

/// Limits on what one request may ask.
struct Limits {
    std::size_t max_body_bytes = 64u << 20;  ///< larger bodies get 413
    std::size_t max_segments = 100000;       ///< segments per lookup (and rows / width per shape) before 413
    std::size_t max_policies = 1000;         ///< policies per observe before 413
    std::size_t max_listed = 10000;          ///< largest `limit` of the segments listing
};

/// The knowledge bases and runs of one file or campaign directory, answering
/// the JSON API (docs/service.md). Thread-safe: lookups of a KB share it,
/// an observation takes it alone and commits before it returns. Files are
/// opened read-only unless `writable` (then KBs are opened for writing).
class KbService {
public:
    /// Loads every KB of `input`: a stepstone file (its KBs, and its run if
    /// it holds one) or a campaign directory (its campaign_kb files and the
    /// runs of campaign.db). Throws ConfigError / DataError / DatabaseError
    /// naming the file.
    KbService(const std::filesystem::path& input, bool writable, Limits limits = {});
    ~KbService();
    KbService(const KbService&) = delete;
    KbService& operator=(const KbService&) = delete;

    const Limits& limits() const { return limits_; }
    bool writable() const { return writable_; }

    /// GET /v1/kbs: every KB's summary.
    nlohmann::json list_kbs() const;
    /// GET /v1/kbs/{name}: its summary, histogram of average rewards and provenance.
    nlohmann::json kb_info(const std::string& name) const;
    /// POST /v1/kbs/{name}/lookup: {"segments": [[dim values], ...]} -> matches and r_max.
    nlohmann::json lookup(const std::string& name, nlohmann::json body) const;
    /// POST /v1/kbs/{name}/shape: {"behaviour": [[channels values], ...]} (rows =
    /// time steps) -> its whole segments' matches and r_max, as evolve computes them.
    nlohmann::json shape(const std::string& name, nlohmann::json body) const;
    /// GET /v1/kbs/{name}/segments: the segments with count >= min_count, by
    /// `order` (reward: largest average first; count; id), at most `limit`.
    nlohmann::json segments(const std::string& name, const std::string& order, std::size_t limit,
                            std::uint64_t min_count, bool values) const;
    /// POST /v1/kbs/{name}/observe: {"run": name, "generation": g, "policies":
    /// [{"behaviour": [[...]], "reward": r}, ...]} observed in order and
    /// committed in one transaction before the answer ("durable": true).
    /// Every policy is checked before any is observed. Refused (403) unless writable.
    nlohmann::json observe(const std::string& name, const nlohmann::json& body);

    /// GET /v1/runs: the runs with their status and progress, read now.
    nlohmann::json runs() const;
    /// GET /v1/runs/{id}/generations: a run's statistics per generation, read now (410 when
    /// its file was deleted; [] for a campaign's run not started yet).
    nlohmann::json generations(std::int64_t id) const;
    /// GET /v1/campaign: the campaign's config, its runs by status and its KBs
    /// (404 when serving a single file).
    nlohmann::json campaign() const;

    /// How often at most the KBs of the input are looked for again (a campaign makes its KBs as
    /// it goes): when a request names or lists KBs.
    static constexpr std::chrono::milliseconds kRescanInterval{1000};

private:
    struct Kb;
    struct RunFile {
        std::int64_t id;
        std::filesystem::path path;
    };
    struct WantedKb {
        std::string name;  // in the API
        std::filesystem::path file;
        std::string stored_name;  // in its file ("": its only one)
    };
    Kb& find(const std::string& name) const;
    std::vector<RunFile> run_files() const;
    bool run_started(std::int64_t id) const;
    std::vector<WantedKb> wanted_kbs() const;
    std::unique_ptr<Kb> load(const WantedKb& wanted) const;
    void rescan() const;

    std::filesystem::path input_;
    bool campaign_ = false;
    bool writable_ = false;
    Limits limits_;
    // the KBs loaded so far: a rescan appends, nothing is removed (a Kb& stays valid)
    mutable std::vector<std::unique_ptr<Kb>> kbs_;
    mutable std::shared_mutex kbs_mutex_;
    mutable std::mutex scan_mutex_;
    mutable std::chrono::steady_clock::time_point last_scan_;
};

/// Everything `stepstone serve` is told.
struct ServeOptions {
    std::filesystem::path input;
    std::string bind = "127.0.0.1";
    int port = 8080;       ///< 0: any free port
    unsigned threads = 0;  ///< requests doing KB work at once; 0 = every core (at least 2)
    unsigned connections = 64;  ///< connections open at once; more wait to be accepted
    bool writable = false;
    std::filesystem::path token_file;  ///< bearer token; required by --writable and a non-loopback --bind
    double timeout_seconds = 30.0;     ///< one request, from its first byte to its answer's last
    Limits limits;
};

/// The HTTP server of `options` bound to its port, not yet serving: what
/// serve() runs, and what `stepstone bench serve` starts in process.
/// Throws as serve() does.
class HttpServer {
public:
    explicit HttpServer(const ServeOptions& options);
    ~HttpServer();
    HttpServer(const HttpServer&) = delete;
    HttpServer& operator=(const HttpServer&) = delete;

    /// The port bound (the free one picked for port 0).
    int port() const;
    /// Answers requests until stop(); then every request in flight is finished.
    void run();
    /// Makes run() return; callable from any thread.
    void stop();

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

/// Serves `options.input` until SIGINT or SIGTERM: then stops accepting,
/// finishes the requests in flight (their observations committed) and
/// returns. Prints "listening on URL" (url_of) on stdout once bound.
/// Throws ConfigError for unsafe or bad options (before binding), Error when
/// the port cannot be bound.
void serve(const ServeOptions& options);

/// http://HOST:PORT, an IPv6 address bracketed: http://[::1]:8080.
std::string url_of(const std::string& host, int port);

/// True for 127.0.0.0/8, ::1 and "localhost".
bool is_loopback(const std::string& host);

/// The dashboard page (GET /): self-contained HTML with its script inline.
std::string_view dashboard_html();

}  // namespace stepstone::service
