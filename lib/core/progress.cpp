#include "core/progress.hpp"

#include <unistd.h>

#include <cmath>

#include "core/text.hpp"

namespace stepstone {

double now_seconds() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

std::string format_duration(double seconds) {
    if (!std::isfinite(seconds) || seconds < 0) return "?";
    auto s = static_cast<long long>(std::llround(seconds));
    char buffer[32];
    if (s >= 3600) {
        std::snprintf(buffer, sizeof buffer, "%lldh%02lldm", s / 3600, (s % 3600) / 60);
    } else if (s >= 60) {
        std::snprintf(buffer, sizeof buffer, "%lldm%02llds", s / 60, s % 60);
    } else {
        std::snprintf(buffer, sizeof buffer, "%llds", s);
    }
    return buffer;
}

Progress::Progress(std::string label, std::uint64_t total, ProgressMode mode, std::FILE* out)
    : label_(std::move(label)), total_(total), out_(out), start_(Clock::now()), last_print_(start_) {
    quiet_ = mode == ProgressMode::quiet;
    bar_ = mode == ProgressMode::bar || (mode == ProgressMode::automatic && isatty(fileno(out_)) != 0);
}

Progress::~Progress() {
    // a bar left mid-line would glue the next message to it
    if (!finished_ && bar_ && !quiet_ && started_) std::fputc('\n', out_);
}

void Progress::update(std::uint64_t done, const std::string& status) {
    if (!started_) {
        // the rate counts only work done since this reporter started (resumed runs)
        started_ = true;
        start_done_ = done;
        start_ = Clock::now();
    }
    done_ = done;
    status_ = status;
    const auto now = Clock::now();
    const auto due = bar_ ? std::chrono::milliseconds(100) : line_interval_;
    if (now - last_print_ >= due) {
        print(false);
        last_print_ = now;
    }
}

void Progress::finish(const std::string& status) {
    if (finished_) return;
    if (!status.empty()) status_ = status;
    print(true);
    finished_ = true;
}

void Progress::print(bool final) {
    if (quiet_) return;
    const double elapsed = std::chrono::duration<double>(Clock::now() - start_).count();
    const double rate = elapsed > 0 ? static_cast<double>(done_ - start_done_) / elapsed : 0.0;
    // append() rather than operator+ chains: g++ 12 raises a false -Wrestrict on those
    std::string line = label_;
    line.append(" ").append(std::to_string(done_));
    if (total_ > 0) line.append("/").append(std::to_string(total_));
    char rate_text[64];
    std::snprintf(rate_text, sizeof rate_text, "  %.3g/s", rate);
    line += rate_text;
    if (total_ > 0 && !final && rate > 0 && done_ < total_) {
        line.append("  ETA ").append(format_duration(static_cast<double>(total_ - done_) / rate));
    }
    if (final) line.append("  in ").append(format_duration(elapsed));
    if (!status_.empty()) line.append("  ").append(status_);

    if (bar_) {
        std::string bar;
        if (total_ > 0) {
            const int width = 24;
            const auto filled = static_cast<int>(width * static_cast<double>(done_) / static_cast<double>(total_));
            bar = "[" + std::string(static_cast<std::size_t>(std::min(filled, width)), '#') +
                  std::string(static_cast<std::size_t>(width - std::min(filled, width)), '.') + "] ";
        }
        std::fprintf(out_, "\r\033[K%s%s%s", bar.c_str(), line.c_str(), final ? "\n" : "");
    } else {
        std::fprintf(out_, "%s\n", line.c_str());
    }
    std::fflush(out_);
}

}  // namespace stepstone
