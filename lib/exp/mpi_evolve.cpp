#include "exp/mpi_evolve.hpp"

#include <algorithm>
#include <chrono>
#include <csignal>
#include <thread>

#include "core/error.hpp"
#include "core/math_fingerprint.hpp"
#include "core/text.hpp"
#include "exp/parallel/bytes.hpp"
#include "exp/parallel/writer_lock.hpp"

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

// the pairs as plain numbers, first and second of each in turn
std::vector<std::uint32_t> flatten(std::span<const evo::PositionPair> pairs) {
    std::vector<std::uint32_t> flat;
    flat.reserve(2 * pairs.size());
    for (const auto& [i, j] : pairs) flat.insert(flat.end(), {i, j});
    return flat;
}

// ------------------------------------------------------------------ rank 0

// At most this many evaluations at a time on rank 0, in lanes (two lanes' worth, ~30 ms): a reply
// waits that long at most, while the rank that sent it has its next chunk already
constexpr std::size_t kOwnEvaluations = 16;

// Rank 0's side of sharing `n` items out: chunks to the other ranks
// (send_chunk(rank, first, count)), whose replies take(message) stores,
// returning how many items it held; while no reply waits, rank 0 does the
// next items itself (do_own(first, count), at most `own_chunk` of them).
// Returns when all n are done. Chunks shrink with the items left (a share of
// them, at least `min_chunk`; rank 0's own at least 1), so that no rank is
// still busy with a large one when the others run out. A signal, or a
// message to or from a rank that died, ends it with EvaluationInterrupted.
template <class SendChunk, class Take, class DoOwn>
void share_out(MpiLeader& leader, std::size_t n, std::size_t min_chunk, std::size_t own_chunk,
               SendChunk send_chunk, Take take, DoOwn do_own) try {
    mpi::Session& session = leader.session();
    const std::size_t shares = 2 * static_cast<std::size_t>(session.size());
    std::size_t next = 0, done = 0;
    auto hand_out = [&](int rank) {
        const std::size_t left = n - next;
        const std::size_t count = std::min(left, std::max(min_chunk, left / shares));
        send_chunk(rank, next, count);  // posted (mpi::Session::post): ranks never wait on each other's sends
        next += count;
    };
    // two chunks to each rank at first, then one a reply: a rank that ends a chunk finds the next waiting
    for (int round = 0; round < 2; ++round) {
        for (int rank = 1; rank < session.size() && next < n; ++rank) hand_out(rank);
    }
    for (int polls = 0; done < n; ++polls) {
        if (InterruptGuard::received()) {
            // mpirun is ending the job (a rank died) or the user stopped it
            throw EvaluationInterrupted{leader.lose()};
        }
        if (auto envelope = session.poll()) {
            polls = 0;
            const auto message = session.receive(*envelope);
            if (message.tag == kTagFailure)
                throw Error(concat(session.describe(message.source), ": ", message.bytes));
            done += take(message);
            if (next < n) hand_out(message.source);
        } else if (next < n) {
            // nothing to read: rank 0 does the next items itself
            const std::size_t left = n - next;
            const std::size_t count = std::min(own_chunk, std::max<std::size_t>(1, left / shares));
            do_own(next, count);
            next += count;
            done += count;
        } else {
            mpi::Session::pause(polls);
        }
    }
    session.flush();
} catch (const mpi::Cancelled&) {
    throw EvaluationInterrupted{leader.lose()};  // a message to or from a rank that died
}

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
        const std::size_t n = genomes.size();
        const std::size_t width = task_->behaviour_size();
        const bool want = behaviours != nullptr;
        std::vector<Evaluation> results(n);
        // rank 0's own chunk's behaviours, recorded only when kept or for r_max (recording costs time)
        std::vector<float> own;
        if (want) behaviours->resize(n * width);  // every slot is written (evaluate_all)
        auto send_chunk = [&](int rank, std::size_t first, std::size_t count) {
            ByteWriter out;
            out.put<std::uint64_t>(first).put<std::uint8_t>(want ? 1 : 0);
            out.put_string(encode_genomes(std::span<const nn::Genome>(genomes).subspan(first, count)));
            session_.post(rank, kTagWork, out.take());
        };
        auto take = [&](const mpi::Message& message) {
            ByteReader in = reply(message, kTagResult);
            const auto first = in.get<std::uint64_t>();
            const auto count = in.get<std::uint64_t>();
            if (first > n || count > n - first) throw malformed(message);
            for (std::size_t k = first; k < first + count; ++k) results[k] = get_evaluation(in);
            if (want) in.get_exactly(std::span<float>(behaviours->data() + first * width, count * width));
            return static_cast<std::size_t>(count);
        };
        // rank 0's own items: in lanes, as a worker's chunk (evaluate_all; a queue of fewer than 4
        // goes one at a time there), each result bit for bit the genome's alone
        auto do_own = [&](std::size_t first, std::size_t count) {
            const auto chunk = std::span<const nn::Genome>(genomes).subspan(first, count);
            std::vector<Evaluation> done =
                evaluate_all(*task_, chunk, dnn_, 1, want || shaping_ ? &own : nullptr);
            for (std::size_t i = 0; i < count; ++i) {
                const std::span<const float> behaviour(own.data() + i * width, want || shaping_ ? width : 0);
                if (shaping_) done[i].r_max = shaped_r_max(*shaping_, behaviour);
                if (want)
                    std::copy(behaviour.begin(), behaviour.end(),
                              behaviours->begin() + static_cast<long>((first + i) * width));
                results[first + i] = std::move(done[i]);
            }
        };
        share_out(leader_, n, 1, kOwnEvaluations, send_chunk, take, do_own);
        return results;
    }

    // the items shared out are batches of evo::kLanes pairs; each rank gets the trajectories with its first
    // chunk
    std::vector<float> distances(std::span<const evo::PositionPair> pairs,
                                 std::span<const evo::Trajectory> trajectories, std::size_t length) override {
        std::vector<float> results(pairs.size());
        const std::size_t batches = (pairs.size() + evo::kLanes - 1) / evo::kLanes;
        const auto pairs_of = [&](std::size_t first, std::size_t count) {
            const std::size_t begin = first * evo::kLanes;
            return pairs.subspan(begin, std::min(count * evo::kLanes, pairs.size() - begin));
        };
        std::vector<evo::GridCell> cells;  // the trajectories end to end, as each rank receives them once
        cells.reserve(trajectories.size() * length);
        for (const auto& t : trajectories) cells.insert(cells.end(), t.begin(), t.end());
        std::vector<char> has_trajectories(static_cast<std::size_t>(session_.size()), 0);
        auto send_chunk = [&](int rank, std::size_t first, std::size_t count) {
            ByteWriter out;
            char& has = has_trajectories[static_cast<std::size_t>(rank)];
            out.put<std::uint8_t>(has ? 0 : 1);
            if (!has) {
                out.put<std::uint64_t>(length).put_span(std::span<const evo::GridCell>(cells));
                has = 1;
            }
            out.put<std::uint64_t>(first).put_span(
                std::span<const std::uint32_t>(flatten(pairs_of(first, count))));
            session_.post(rank, kTagPairs, out.take());
        };
        auto take = [&](const mpi::Message& message) {
            ByteReader in = reply(message, kTagDistances);
            const auto first = in.get<std::uint64_t>();
            std::vector<float> received;
            in.get_into(received);
            if (first >= batches || received.size() > results.size() - first * evo::kLanes)
                throw malformed(message);
            std::copy(received.begin(), received.end(),
                      results.begin() + static_cast<long>(first * evo::kLanes));
            return (received.size() + evo::kLanes - 1) / evo::kLanes;
        };
        auto do_own = [&](std::size_t first, std::size_t count) {
            const auto own = evo::pair_distances(pairs_of(first, count), trajectories, length, 1);
            std::copy(own.begin(), own.end(), results.begin() + static_cast<long>(first * evo::kLanes));
        };
        // a batch takes tens of microseconds: fewer than 8 a message would cost more than they save;
        // rank 0 takes one at a time, so that it reads a reply within tens of microseconds
        share_out(leader_, batches, 8, 1, send_chunk, take, do_own);
        return results;
    }

private:
    // a reply of `tag` from a worker, or an error naming the rank that sent something else
    ByteReader reply(const mpi::Message& message, int tag) const {
        if (message.tag != tag) {
            throw Error(concat(session_.describe(message.source), " sent an unexpected message (tag ",
                               message.tag, ")"));
        }
        return ByteReader(message.bytes);
    }
    // a reply whose items are not among those handed out
    Error malformed(const mpi::Message& message) const {
        return Error(concat(session_.describe(message.source), " sent results for items it was not given"));
    }

    MpiLeader& leader_;
    mpi::Session& session_;
    std::shared_ptr<const sim::Task> task_;
    nn::DnnConfig dnn_;
    const kb::KnowledgeBase* shaping_;
};

// ---------------------------------------------------------------- workers

// one kTagWork message: its genomes evaluated on `threads` threads, the reply's bytes
std::string evaluate_chunk(const std::string& bytes, const sim::Task& task, const runs::EvolveConfig& config,
                           const kb::KnowledgeBase* shaping, unsigned threads,
                           std::vector<float>& behaviours) {
    ByteReader in(bytes);
    const auto first = in.get<std::uint64_t>();
    const bool want = in.get<std::uint8_t>() != 0;
    // behaviours recorded only when rank 0 keeps them or r_max needs them (recording costs time)
    const std::size_t width = want || shaping ? task.behaviour_size() : 0;
    const auto genomes = decode_genomes(in.get_string());
    // as a process's own generation: queues of similar policies in lanes (evaluate_all), each result
    // bit for bit the policy's alone; the buffer is kept from chunk to chunk, every slot written
    std::vector<Evaluation> results =
        evaluate_all(task, genomes, config.dnn, threads, width > 0 ? &behaviours : nullptr);
    if (shaping) {
        parallel_for(genomes.size(), threads, [&](std::size_t k) {
            results[k].r_max =
                shaped_r_max(*shaping, std::span<const float>(behaviours.data() + k * width, width));
        });
    }
    ByteWriter out;
    // room for the behaviours too (tens of MB in a KB-observing generation): one allocation, no regrowth
    out.reserve(64 + genomes.size() * (128 + task.cell_count() * sizeof(evo::GridCell)) +
                (want ? genomes.size() * width * sizeof(float) : 0));
    out.put<std::uint64_t>(first).put<std::uint64_t>(genomes.size());
    for (const auto& result : results) put_evaluation(out, result);
    if (want) out.put_span(std::span<const float>(behaviours.data(), genomes.size() * width));
    return out.take();  // not a copy: a reply can hold tens of MB
}

// the trajectories of the generation whose distances a worker computes
struct PairSetting {
    std::vector<evo::Trajectory> trajectories;
    std::size_t length = 0;
};

// one kTagPairs message: its pairs' distances on `threads` threads, the reply's bytes
std::string distance_chunk(const std::string& bytes, PairSetting& setting, unsigned threads) {
    ByteReader in(bytes);
    if (in.get<std::uint8_t>() != 0) {
        setting.length = in.get<std::uint64_t>();
        std::vector<evo::GridCell> cells;
        in.get_into(cells);
        if (setting.length == 0 || cells.size() % setting.length != 0)
            throw Error("rank 0 sent malformed trajectories");
        setting.trajectories.clear();
        for (auto at = cells.begin(); at != cells.end(); at += static_cast<long>(setting.length)) {
            setting.trajectories.emplace_back(at, at + static_cast<long>(setting.length));
        }
    }
    const auto first = in.get<std::uint64_t>();
    std::vector<std::uint32_t> flat;
    in.get_into(flat);
    std::vector<evo::PositionPair> pairs;
    for (std::size_t k = 0; k + 1 < flat.size(); k += 2) {
        if (std::max(flat[k], flat[k + 1]) >= setting.trajectories.size())
            throw Error("rank 0 sent a pair out of range");
        pairs.emplace_back(flat[k], flat[k + 1]);
    }
    ByteWriter out;
    out.put<std::uint64_t>(first).put_span(
        std::span<const float>(evo::pair_distances(pairs, setting.trajectories, setting.length, threads)));
    return out.take();  // not a copy: a reply can hold tens of MB
}

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
    nlohmann::json setup = {
        {"config", config.to_json()}, {"run", run}, {"math_fingerprint", math_fingerprint()}};
    for (int rank = 1; rank < session_.size(); ++rank) session_.send(rank, kTagSetup, setup.dump());
    return std::make_unique<MpiEvaluator>(*this, config, shaping);
}

void serve_evolve(mpi::Session& session, unsigned threads) {
    std::signal(SIGINT, SIG_IGN);
    std::signal(SIGTERM, SIG_IGN);
    auto next = [&] { return *session.wait([] { return true; }); };
    auto message = next();
    if (message.tag == kTagStop) return;  // rank 0 stopped before the run began (bad input)
    try {
        const auto setup = nlohmann::json::parse(message.bytes);
        runs::EvolveConfig config = runs::EvolveConfig::from_json(setup.at("config"), "rank 0's config", {},
                                                                  runs::ConfigOrigin::stored);
        // a rank whose math library rounds otherwise would evaluate some policies differently from rank 0
        // (unless the run uses portable math)
        const auto leader_math = setup.at("math_fingerprint").get<std::string>();
        if (config.math() == Math::libm && leader_math != math_fingerprint()) {
            throw Error(concat("this rank's math library rounds differently from rank 0's (math fingerprint ",
                               math_fingerprint(), ", rank 0's ", leader_math,
                               "), so the run would depend on which rank evaluates what; run every rank on "
                               "machines of one kind, or give the run \"math\": \"portable\""));
        }
        std::optional<kb::KnowledgeBase> shaping;
        if (config.transfer && !config.transfer->kb.empty())
            shaping = load_shaping_kb(config);  // checked against rank 0's digest
        const auto task = sim::make_task(config.task);
        PairSetting pairs;
        std::vector<float> behaviours;
        for (message = next(); message.tag == kTagWork || message.tag == kTagPairs; message = next()) {
            // posted: the next chunk, already waiting, starts before rank 0 has taken this one
            if (message.tag == kTagWork) {
                session.post(0, kTagResult,
                             evaluate_chunk(message.bytes, *task, config, shaping ? &*shaping : nullptr,
                                            threads, behaviours));
            } else {
                session.post(0, kTagDistances, distance_chunk(message.bytes, pairs, threads));
            }
        }
    } catch (const std::exception& e) {
        // rank 0 reports it and stops the job: this rank waits for its word
        session.send(0, kTagFailure, one_line(e.what()));
        while (next().tag != kTagStop) {
        }
    }
}

}  // namespace stepstone::exp
