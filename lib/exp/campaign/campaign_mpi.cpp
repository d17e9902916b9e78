#include "exp/campaign/campaign_mpi.hpp"

#include <chrono>
#include <csignal>
#include <fstream>
#include <iostream>
#include <map>
#include <thread>

#include "core/error.hpp"
#include "core/progress.hpp"
#include "core/text.hpp"
#include "exp/evolution.hpp"
#include "exp/mpi_evolve.hpp"
#include "exp/parallel/writer_lock.hpp"

namespace stepstone::exp {

namespace fs = std::filesystem;

namespace {

nlohmann::json launch_to_json(const RunLaunch& launch) {
    nlohmann::json json = {
        {"index", launch.index},   {"config", launch.config.string()},  {"db", launch.db.string()},
        {"seed", launch.seed},     {"generations", launch.generations}, {"threads", launch.threads},
        {"resume", launch.resume}, {"log", launch.log.string()}};
    if (launch.kb) {
        json["kb"] = launch.kb->string();
        json["treatment"] = to_string(*launch.treatment);
    }
    if (launch.seed_from) {
        json["seed_from"] = launch.seed_from->string();
        json["seed_with"] = to_string(*launch.seed_with);
        if (launch.seed_count) json["seed_count"] = *launch.seed_count;
    }
    return json;
}

RunLaunch launch_from_json(const nlohmann::json& json) {
    RunLaunch launch;
    launch.index = json.at("index").get<std::size_t>();
    launch.config = json.at("config").get<std::string>();
    launch.db = json.at("db").get<std::string>();
    launch.seed = json.at("seed").get<std::uint64_t>();
    launch.generations = json.at("generations").get<int>();
    launch.threads = json.at("threads").get<unsigned>();
    launch.resume = json.at("resume").get<bool>();
    launch.log = json.at("log").get<std::string>();
    if (json.contains("kb")) {
        launch.kb = json.at("kb").get<std::string>();
        launch.treatment = runs::parse_treatment(json.at("treatment").get<std::string>(), "treatment");
    }
    if (json.contains("seed_from")) {
        launch.seed_from = json.at("seed_from").get<std::string>();
        launch.seed_with = runs::parse_seed_with(json.at("seed_with").get<std::string>(), "seed_with");
        if (json.contains("seed_count")) launch.seed_count = json.at("seed_count").get<int>();
    }
    return launch;
}

// runs `launch` in this process as `stepstone evolve` would, its error line appended to its log
RunEnd run_in_process(const RunLaunch& launch) {
    EvolveOptions options = launch.evolve_options();
    options.stop_on_signals = false;  // the MPI job's signals are rank 0's business
    RunEnd end{launch.index, true, ""};
    // the run's warnings and error go to its log, as a child process's would
    std::ofstream log(launch.log, std::ios::app);
    std::streambuf* const stderr_buffer = std::cerr.rdbuf(log.rdbuf());
    try {
        run_evolve(options);
    } catch (const std::exception& e) {
        end.ok = false;
        end.error = one_line(e.what());
        std::cerr << "stepstone: error: " << end.error << "\n";
    }
    std::cerr.rdbuf(stderr_buffer);
    return end;
}

class MpiExecutor final : public RunExecutor {
public:
    explicit MpiExecutor(MpiLeader& leader) : leader_(leader), session_(leader.session()) {}

    std::size_t slots() const override {
        return session_.size() > 1 ? static_cast<std::size_t>(session_.size() - 1) : 1;
    }

    bool runs_here() const override { return session_.size() == 1; }

    // a rank is a core (Slurm's --ntasks); more threads with --threads and --cpus-per-task
    unsigned default_threads(std::size_t) const override { return 1; }

    void start(const RunLaunch& launch) override {
        try {
            start_on_a_rank(launch);
        } catch (const mpi::Cancelled&) {
            lost();
        }
    }

    std::vector<RunEnd> wait() override {
        try {
            return wait_for_ranks();
        } catch (const mpi::Cancelled&) {
            lost();
        }
    }

private:
    void start_on_a_rank(const RunLaunch& launch) {
        if (session_.size() == 1) {
            alone_.push_back(launch);  // run by wait(), here
            return;
        }
        for (int rank = 1; rank < session_.size(); ++rank) {
            if (busy_.count(rank)) continue;
            session_.send(rank, kTagSetup, launch_to_json(launch).dump());
            busy_.emplace(rank, launch);
            return;
        }
        throw Error("campaign: no free rank for a run (internal)");
    }

    std::vector<RunEnd> wait_for_ranks() {
        std::vector<RunEnd> ended;
        for (const auto& launch : alone_) ended.push_back(run_in_process(launch));
        alone_.clear();
        const double until = now_seconds() + 0.1;
        for (int polls = 0; ended.empty() && now_seconds() < until; ++polls) {
            if (InterruptGuard::received()) lost();
            if (auto envelope = session_.poll()) {
                const auto message = session_.receive(*envelope);
                const auto json = nlohmann::json::parse(message.bytes);
                ended.push_back({json.at("index").get<std::size_t>(), json.at("ok").get<bool>(),
                                 json.at("error").get<std::string>()});
                busy_.erase(message.source);
                continue;
            }
            mpi::Session::pause(polls);
        }
        return ended;
    }

    // mpirun is ending the job: name the dead rank and its run, and leave without MPI_Finalize
    [[noreturn]] void lost() {
        const auto dead = session_.lost_ranks();
        leader_.abandon();
        const std::string after = concat(
            "; every run file keeps its last committed generation; continue with ", option_name("resume"));
        if (dead.empty()) {
            throw Interrupted(
                concat("campaign stopped: the MPI job is being ended (cancelled, or a rank on another "
                       "host was lost)",
                       after));
        }
        std::string runs;
        for (int rank : dead) {
            const auto it = busy_.find(rank);
            runs += concat(runs.empty() ? "" : "; ", session_.describe(rank), " died ",
                           it == busy_.end() ? std::string("between runs")
                                             : concat("while running ", it->second.db.string()));
        }
        throw Error(concat("campaign stopped: ", runs, after));
    }

    MpiLeader& leader_;
    mpi::Session& session_;
    std::map<int, RunLaunch> busy_;  // worker rank -> its run
    std::vector<RunLaunch> alone_;   // a single rank's runs, run in wait()
    InterruptGuard interrupts_;      // mpirun's SIGTERM is noticed in wait()
};

}  // namespace

std::unique_ptr<RunExecutor> make_mpi_executor(MpiLeader& leader) {
    return std::make_unique<MpiExecutor>(leader);
}

void serve_campaign(mpi::Session& session) {
    std::signal(SIGINT, SIG_IGN);
    std::signal(SIGTERM, SIG_IGN);
    for (;;) {
        const auto message = *session.wait([] { return true; });
        if (message.tag == kTagStop) return;
        const RunEnd end = run_in_process(launch_from_json(nlohmann::json::parse(message.bytes)));
        const nlohmann::json reply = {{"index", end.index}, {"ok", end.ok}, {"error", end.error}};
        session.send(0, kTagResult, reply.dump());
    }
}

}  // namespace stepstone::exp
