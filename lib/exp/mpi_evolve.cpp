#include "exp/mpi_evolve.hpp"

#include <algorithm>
#include <chrono>
#include <csignal>
#include <thread>

#include "core/bytes.hpp"
#include "core/error.hpp"
#include "core/text.hpp"
#include "core/writer_lock.hpp"

namespace stepstone::exp {

namespace {

// ------------------------------------------------------------------- wire

std::string encode_genomes(std::span<const nn::Genome> genomes) {
    auto array = nlohmann::json::array();
    for (const auto& genome : genomes) array.push_back(genome.to_json());
    const auto cbor = nlohmann::json::to_cbor(array);  // doubles kept exactly
    return std::string(cbor.begin(), cbor.end());
}

std::vector<nn::Genome> decode_genomes(const std::string& bytes) {
    std::vector<nn::Genome> genomes;
    for (const auto& json : nlohmann::json::from_cbor(bytes)) genomes.push_back(nn::Genome::from_json(json));
    return genomes;
}

void put_evaluation(ByteWriter& out, const Evaluation& e) {
    out.put(e.reward).put<std::int64_t>(e.balls).put<std::int64_t>(e.steps).put<std::int64_t>(e.nan_outputs);
    const sim::Milestones& m = e.milestones;
    out.put<std::int64_t>(m.presses).put<std::int64_t>(m.pickups).put<std::int64_t>(m.carry_steps);
    out.put<std::int64_t>(m.basket_releases);
    out.put_span(std::span<const evo::GridCell>(e.cells));
    out.put<std::uint8_t>(e.r_max ? 1 : 0).put(e.r_max.value_or(0.0));
}

Evaluation get_evaluation(ByteReader& in) {
    Evaluation e;
    e.reward = in.get<double>();
    e.balls = static_cast<int>(in.get<std::int64_t>());
    e.steps = static_cast<long>(in.get<std::int64_t>());
    e.nan_outputs = static_cast<int>(in.get<std::int64_t>());
    e.milestones.presses = static_cast<int>(in.get<std::int64_t>());
    e.milestones.pickups = static_cast<int>(in.get<std::int64_t>());
    e.milestones.carry_steps = static_cast<long>(in.get<std::int64_t>());
    e.milestones.basket_releases = static_cast<int>(in.get<std::int64_t>());
    in.get_into(e.cells);
    const bool has_r_max = in.get<std::uint8_t>() != 0;
    const double r_max = in.get<double>();
    if (has_r_max) e.r_max = r_max;
    return e;
}

// one genome as every rank evaluates it: the episode, then r_max under the shaping KB
Evaluation evaluate_one(const sim::Task& task, const nn::Genome& genome, const nn::DnnConfig& dnn,
                        const kb::KnowledgeBase* shaping, std::span<float> behaviour) {
    Evaluation evaluation = evaluate_genome(task, genome, dnn, behaviour);
    if (shaping) evaluation.r_max = shaped_r_max(*shaping, behaviour);
    return evaluation;
}

// ------------------------------------------------------------------ rank 0

class MpiEvaluator final : public RemoteEvaluator {
public:
    MpiEvaluator(MpiLeader& leader, const runs::EvolveConfig& config, const kb::KnowledgeBase* shaping)
        : leader_(leader),
          session_(leader.session()),
          task_(sim::make_task(config.task)),
          dnn_(config.dnn),
          shaping_(shaping) {}

    std::vector<Evaluation> evaluate(const std::vector<nn::Genome>& genomes,
                                     std::vector<float>* behaviours) override {
        try {
            return evaluate_over_ranks(genomes, behaviours);
        } catch (const mpi::Cancelled&) {
            throw EvaluationInterrupted{leader_.lose()};  // a message to or from a rank that died
        }
    }

private:
    std::vector<Evaluation> evaluate_over_ranks(const std::vector<nn::Genome>& genomes,
                                                std::vector<float>* behaviours) {
        const std::size_t n = genomes.size();
        const std::size_t width = task_->behaviour_size();
        const bool want = behaviours != nullptr;
        std::vector<Evaluation> results(n);
        std::vector<float> own(width);  // rank 0's own evaluations, when not kept
        if (want) behaviours->assign(n * width, 0.0f);
        // small chunks: ranks that finish early (policies that stand still) take more
        const std::size_t chunk =
            std::max<std::size_t>(1, n / (4 * static_cast<std::size_t>(session_.size())));
        std::size_t next = 0, done = 0;
        auto hand_out = [&](int rank) {
            const std::size_t count = std::min(chunk, n - next);
            ByteWriter out;
            out.put<std::uint64_t>(next).put<std::uint8_t>(want ? 1 : 0);
            out.put_string(encode_genomes(std::span<const nn::Genome>(genomes).subspan(next, count)));
            session_.send(rank, kTagWork, out.bytes());
            next += count;
        };
        for (int rank = 1; rank < session_.size() && next < n; ++rank) hand_out(rank);
        for (int polls = 0; done < n; ++polls) {
            if (InterruptGuard::received()) {
                // mpirun is ending the job (a rank died) or the user stopped it
                throw EvaluationInterrupted{leader_.lose()};
            }
            if (auto envelope = session_.poll()) {
                polls = 0;
                const auto message = session_.receive(*envelope);
                if (message.tag == kTagFailure) {
                    throw Error(concat(session_.describe(message.source), ": ", message.bytes));
                }
                ByteReader in(message.bytes);
                const auto first = in.get<std::uint64_t>();
                const auto count = in.get<std::uint64_t>();
                for (std::size_t k = first; k < first + count; ++k) results[k] = get_evaluation(in);
                if (want) {
                    std::vector<float> received;
                    in.get_into(received);
                    std::copy(received.begin(), received.end(),
                              behaviours->begin() + static_cast<long>(first * width));
                }
                done += count;
                if (next < n) hand_out(message.source);
            } else if (next < n) {
                // nothing to read: rank 0 evaluates the next genome itself
                const std::size_t k = next++;
                const std::span<float> behaviour =
                    want ? std::span<float>(behaviours->data() + k * width, width) : std::span<float>(own);
                results[k] = evaluate_one(*task_, genomes[k], dnn_, shaping_, behaviour);
                ++done;
            } else {
                mpi::Session::pause(polls);
            }
        }
        return results;
    }

    MpiLeader& leader_;
    mpi::Session& session_;
    std::shared_ptr<const sim::Task> task_;
    nn::DnnConfig dnn_;
    const kb::KnowledgeBase* shaping_;
};

}  // namespace

std::string MpiLeader::lose() {
    abandon();
    std::string dead;
    for (int rank : session_.lost_ranks()) dead += concat(dead.empty() ? "" : ", ", session_.describe(rank));
    return dead.empty() ? dead : dead + " died";
}

MpiLeader::MpiLeader(mpi::Session& session) : session_(session) {
    session_.set_cancel([] { return InterruptGuard::received() != 0; });
}

MpiLeader::~MpiLeader() {
    if (abandoned_) return;
    for (int rank = 1; rank < session_.size(); ++rank) {
        try {
            session_.send(rank, kTagStop, "");
        } catch (const Error&) {
            // that rank is gone: mpirun ends the job
        }
    }
}

void MpiLeader::abandon() {
    abandoned_ = true;
    session_.abandon();
}

std::unique_ptr<RemoteEvaluator> MpiLeader::start(const runs::EvolveConfig& config,
                                                  const kb::KnowledgeBase* shaping, const std::string& run) {
    nlohmann::json setup = {{"config", config.to_json()}, {"run", run}};
    for (int rank = 1; rank < session_.size(); ++rank) session_.send(rank, kTagSetup, setup.dump());
    return std::make_unique<MpiEvaluator>(*this, config, shaping);
}

// ---------------------------------------------------------------- workers

void serve_evolve(mpi::Session& session, unsigned threads) {
    std::signal(SIGINT, SIG_IGN);
    std::signal(SIGTERM, SIG_IGN);
    auto next = [&] { return *session.wait([] { return true; }); };
    auto message = next();
    if (message.tag == kTagStop) return;  // rank 0 stopped before the run began (bad input)
    try {
        const auto setup = nlohmann::json::parse(message.bytes);
        runs::EvolveConfig config = runs::EvolveConfig::from_json(setup.at("config"), "rank 0's config");
        std::optional<kb::KnowledgeBase> shaping;
        if (config.transfer) shaping = load_shaping_kb(config);  // checked against rank 0's digest
        const auto task = sim::make_task(config.task);
        const std::size_t width = task->behaviour_size();
        for (message = next(); message.tag == kTagWork; message = next()) {
            ByteReader in(message.bytes);
            const auto first = in.get<std::uint64_t>();
            const bool want = in.get<std::uint8_t>() != 0;
            const auto genomes = decode_genomes(in.get_string());
            std::vector<Evaluation> results(genomes.size());
            std::vector<float> behaviours(genomes.size() * width);
            parallel_for(genomes.size(), threads, [&](std::size_t k) {
                results[k] = evaluate_one(*task, genomes[k], config.dnn, shaping ? &*shaping : nullptr,
                                          std::span<float>(behaviours.data() + k * width, width));
            });
            ByteWriter out;
            out.put<std::uint64_t>(first).put<std::uint64_t>(genomes.size());
            for (const auto& result : results) put_evaluation(out, result);
            if (want) out.put_span(std::span<const float>(behaviours));
            session.send(0, kTagResult, out.bytes());
        }
    } catch (const std::exception& e) {
        // rank 0 reports it and stops the job: this rank waits for its word
        session.send(0, kTagFailure, one_line(e.what()));
        while (next().tag != kTagStop) {
        }
    }
}

}  // namespace stepstone::exp
