#pragma once

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <string>

namespace stepstone {

/// How a Progress reporter writes.
enum class ProgressMode {
    automatic,  ///< a redrawn bar on a terminal, a line every few seconds otherwise
    bar,        ///< always the redrawn bar
    lines,      ///< always plain lines
    quiet,      ///< nothing (--quiet)
};

/// Progress of long work on stderr: done / total, rate, ETA and a free-form
/// status ("best 0.25"). Not thread-safe: call it from the coordinating thread.
class Progress {
public:
    /// `label` names the work ("generation"), `total` its size (0 = unknown),
    /// `unit` what the rate counts ("gen").
    Progress(std::string label, std::uint64_t total, ProgressMode mode = ProgressMode::automatic,
             std::FILE* out = stderr);
    ~Progress();
    Progress(const Progress&) = delete;
    Progress& operator=(const Progress&) = delete;

    /// Records that `done` units are complete; prints when due.
    void update(std::uint64_t done, const std::string& status = "");
    /// Prints the final state and ends the bar's line.
    void finish(const std::string& status = "");

    /// Interval between plain lines (default 5 s); 0 prints every update.
    void set_line_interval(std::chrono::milliseconds interval) { line_interval_ = interval; }

private:
    void print(bool final);

    using Clock = std::chrono::steady_clock;
    std::string label_;
    std::uint64_t total_;
    std::uint64_t done_ = 0;
    std::uint64_t start_done_ = 0;
    bool started_ = false;
    std::string status_;
    bool bar_;
    bool quiet_;
    bool finished_ = false;
    std::FILE* out_;
    Clock::time_point start_;
    Clock::time_point last_print_;
    std::chrono::milliseconds line_interval_{5000};
};

/// Seconds on the steady clock, for measuring durations (the origin is arbitrary).
double now_seconds();

/// "1h02m", "3m05s" or "12s".
std::string format_duration(double seconds);

}  // namespace stepstone
