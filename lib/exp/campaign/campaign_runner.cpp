#include "exp/campaign/campaign_runner.hpp"

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <deque>
#include <map>
#include <thread>

#include "core/assert.hpp"
#include "core/error.hpp"
#include "core/text.hpp"
#include "db/database.hpp"
#include "db/digest.hpp"
#include "exp/evaluation.hpp"
#include "exp/parallel/child_process.hpp"
#include "exp/parallel/writer_lock.hpp"

namespace stepstone::exp {

namespace fs = std::filesystem;

namespace {

class ProcessExecutor final : public RunExecutor {
public:
    ProcessExecutor(RunCommand command, unsigned jobs)
        : command_(std::move(command)), jobs_(resolve_threads(jobs)) {}

    std::size_t slots() const override { return jobs_; }

    unsigned default_threads(std::size_t at_once) const override {
        // results do not depend on threads: idle cores go to the runs of a small step
        return std::max(1u, resolve_threads(0) / static_cast<unsigned>(at_once));
    }

    void start(const RunLaunch& launch) override {
        active_.emplace(spawn_child(command_(launch.evolve_options()), launch.log), launch);
    }

    std::vector<RunEnd> wait() override {
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
        std::vector<RunEnd> ended;
        for (const ChildExit& child : reap_children()) {
            const auto it = active_.find(child.pid);
            if (it == active_.end()) continue;
            RunEnd end{it->second.index, exited_cleanly(child.status), "", stopped_on_request(child.status)};
            if (!end.ok) end.error = describe_exit(child.status, last_line_of(it->second.log));
            active_.erase(it);
            ended.push_back(end);
        }
        return ended;
    }

    void interrupt() override {
        for (const auto& [pid, launch] : active_) ::kill(pid, SIGTERM);
    }

private:
    RunCommand command_;
    std::size_t jobs_;
    std::map<pid_t, RunLaunch> active_;
};

}  // namespace

std::unique_ptr<RunExecutor> make_process_executor(RunCommand command, unsigned jobs) {
    if (!command)
        throw ConfigError("a campaign whose runs are child processes needs their command (run_command)");
    return std::make_unique<ProcessExecutor>(std::move(command), jobs);
}

EvolveOptions RunLaunch::evolve_options() const {
    EvolveOptions options;
    options.config_path = config;
    options.db_path = db;
    options.seed = seed;
    options.generations = generations;
    options.threads = threads;
    options.resume = resume;
    options.kb = kb;
    options.treatment = treatment;
    options.seed_from = seed_from;
    options.seed_with = seed_with;
    options.seed_count = seed_count;
    options.progress = ProgressMode::quiet;
    return options;
}

fs::path run_log_path(const fs::path& dir, const runs::PlannedRun& run) {
    std::string name = run.file;
    std::replace(name.begin(), name.end(), '/', '-');
    return dir / "logs" / (fs::path(name).replace_extension(".log"));
}

Runner::Runner(const CampaignOptions& options, db::Connection& connection,
               std::vector<runs::CampaignRun>& runs, Progress& progress, RunExecutor& executor)
    : options_(options), connection_(connection), runs_(runs), progress_(progress), executor_(executor) {}

void Runner::set_seeding(fs::path source, const runs::CampaignSeed& seed) {
    seed_source_ = std::move(source);
    seed_ = seed;
}

std::vector<std::string> Runner::execute(const std::vector<std::size_t>& indices, CampaignSummary& summary) {
    std::deque<std::size_t> queue;
    for (std::size_t k : indices) {
        auto& state = runs_[k];
        const fs::path file = options_.dir / state.run.file;
        if (state.status == runs::RunStatus::finished && !fs::exists(file)) {
            std::fprintf(stderr,
                         "campaign: %s is missing though campaign.db records it finished; running it again\n",
                         state.run.file.c_str());
        }
        const auto on_disk = existing_state(k);
        if (on_disk && on_disk->finished && on_disk->generations_done >= state.run.generations) {
            mark_finished(k, *on_disk, 0.0);
            ++summary.skipped;
            continue;
        }
        queue.push_back(k);
    }
    const std::size_t at_once = std::max<std::size_t>(1, std::min(executor_.slots(), queue.size()));
    const unsigned threads = options_.threads > 0 ? options_.threads : executor_.default_threads(at_once);
    std::vector<std::string> failures;
    std::vector<Active> active;
    bool stopping = false;
    while (!queue.empty() || !active.empty()) {
        if (InterruptGuard::received() && !stopping) {
            // Ctrl-C or SIGTERM: no new run; the running ones end their generation
            stopping = true;
            queue.clear();
            executor_.interrupt();
        }
        while (!queue.empty() && active.size() < executor_.slots()) {
            const std::size_t k = queue.front();
            queue.pop_front();
            executor_.start(launch_of(k, threads));
            runs_[k].status = runs::RunStatus::running;
            update_run_row(connection_, runs_[k], std::nullopt, 0.0, std::nullopt);
            active.push_back(Active{k, now_seconds()});
        }
        for (const RunEnd& end : executor_.wait()) {
            const auto it = std::find_if(active.begin(), active.end(),
                                         [&](const Active& a) { return a.index == end.index; });
            if (it == active.end()) continue;
            const Active done = *it;
            active.erase(it);
            if (auto failure = finish(done, end)) failures.push_back(*failure);
        }
        report(active);
    }
    return failures;
}

std::optional<runs::RunFileState> Runner::existing_state(std::size_t k) {
    try {
        return runs::read_run_file(options_.dir / runs_[k].run.file);
    } catch (const Error&) {
        return runs::RunFileState{};  // present but unreadable: evolve --resume reports why
    }
}

void Runner::mark_finished(std::size_t k, const runs::RunFileState& on_disk, double wall_time) {
    auto& state = runs_[k];
    state.status = runs::RunStatus::finished;
    state.generations_done = on_disk.generations_done;
    state.best_reward = on_disk.best_reward;
    auto run_connection = db::open_database(options_.dir / state.run.file, db::OpenMode::read_only);
    update_run_row(connection_, state, db::run_digest(run_connection), wall_time, std::nullopt);
}

RunLaunch Runner::launch_of(std::size_t k, unsigned threads) const {
    const auto& state = runs_[k];
    const fs::path file = options_.dir / state.run.file;
    fs::create_directories(file.parent_path());
    fs::create_directories(options_.dir / "logs");
    RunLaunch launch;
    launch.index = k;
    launch.log = run_log_path(options_.dir, state.run);
    launch.config = options_.dir / "config" / concat(to_string(state.run.step), ".json");
    launch.db = file;
    launch.seed = state.run.seed;
    launch.generations = state.run.generations;
    launch.threads = threads;
    launch.resume = fs::exists(file);
    if (state.run.step == runs::CampaignStep::target && needs_kb(state.run.treatment)) {
        launch.kb =
            options_.dir / (needs_randomized_kb(state.run.treatment) ? runs::kRandomKbFile : runs::kKbFile);
        launch.treatment = shaping_of(state.run.treatment);
    }
    if (state.run.step == runs::CampaignStep::target && is_seeded(state.run.treatment)) {
        STEPSTONE_ASSERT(seed_source_.has_value());
        launch.seed_from = *seed_source_;
        launch.seed_with = seed_.with;
        launch.seed_count = seed_.count;
    }
    return launch;
}

std::optional<std::string> Runner::finish(const Active& done, const RunEnd& end) {
    auto& state = runs_[done.index];
    const double wall = now_seconds() - done.started;
    // the run's process has ended, but a progress reading (report()) may have
    // held its file as it closed it, which leaves the file in WAL mode
    if (executor_.runs_here()) db::settle_journal(options_.dir / state.run.file);
    if (end.stopped && InterruptGuard::received()) {
        // its file keeps every committed generation: a resume continues it
        state.status = runs::RunStatus::pending;
        update_run_row(connection_, state, std::nullopt, wall, std::nullopt);
        return std::nullopt;
    }
    if (end.ok) {
        try {
            const auto on_disk = runs::read_run_file(options_.dir / state.run.file);
            if (on_disk && on_disk->finished) {
                mark_finished(done.index, *on_disk, wall);
                return std::nullopt;
            }
        } catch (const Error&) {
        }
    }
    const std::string error =
        end.error.empty() ? last_line_of(run_log_path(options_.dir, state.run)) : end.error;
    state.status = runs::RunStatus::failed;
    update_run_row(connection_, state, std::nullopt, wall, error);
    return concat(state.run.file, ": ", error);
}

void Runner::report(const std::vector<Active>& active) {
    const double now = now_seconds();
    const bool read_files = executor_.runs_here() && now - last_reading_ >= kReadingPeriod;
    if (read_files) last_reading_ = now;
    std::uint64_t done = 0;
    std::size_t finished = 0;
    for (auto& state : runs_) {
        if (state.status == runs::RunStatus::running && read_files) {
            try {
                if (auto on_disk = runs::read_run_file(options_.dir / state.run.file)) {
                    state.generations_done = on_disk->generations_done;
                }
            } catch (const Error&) {
                // being created or busy: keep the last reading
            }
        }
        if (state.status == runs::RunStatus::finished) ++finished;
        done += static_cast<std::uint64_t>(std::max(0, state.generations_done + 1));
    }
    std::string status = concat("runs ", finished, "/", runs_.size());
    for (const auto& run : active) {
        const auto& state = runs_[run.index];
        status += concat(
            "  ",
            std::string(state.run.step == runs::CampaignStep::source ? to_string(state.run.step)
                                                                     : to_string(state.run.treatment)),
            "/", state.run.seed, " g", std::max(0, state.generations_done), "/", state.run.generations);
    }
    progress_.update(done, status);
}

}  // namespace stepstone::exp
