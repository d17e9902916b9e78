// The JSON API of a KB file, run file or campaign directory, without HTTP.

#include "service/service.hpp"

#include <algorithm>
#include <cmath>
#include <mutex>
#include <optional>
#include <shared_mutex>

#include "core/error.hpp"
#include "core/text.hpp"
#include "db/database.hpp"
#include "db/kb_store.hpp"
#include "kb/segments.hpp"
#include "runs/campaign_store.hpp"
#include "runs/kb_stats.hpp"
#include "runs/run_series.hpp"
#include "runs/run_store.hpp"
#include "service/body.hpp"

namespace stepstone::service {

namespace fs = std::filesystem;
using nlohmann::json;

struct KbService::Kb {
    std::string name;        // as the API names it
    std::string stored_name; // in its file
    fs::path file;
    std::int64_t id = 0;     // in its file
    std::optional<std::uint64_t> randomized_seed;
    kb::KnowledgeBase kb{kb::KbParams{}};
    mutable std::shared_mutex mutex;  // shared: lookups; alone: observe
    std::optional<db::Connection> writer;
};

namespace {

json match_json(std::size_t index, const kb::SegmentMatch& m) {
    return {{"segment", index},
            {"kb_segment_id", m.id ? json(*m.id) : json()},
            {"distance", m.distance},
            {"average_reward", m.average_reward}};
}

// a behaviour matrix (rows of `channels` values) flattened: the packed matrix itself, or `storage`
std::span<const float> read_behaviour(const json& rows, const kb::KbParams& params, const std::string& what,
                                      const Limits& limits, std::vector<float>& storage) {
    const std::size_t count = row_count(rows);
    if (count == 0) throw HttpError(400, what + " must be a non-empty array of rows");
    if (count < params.segment_width) {
        throw HttpError(400, concat(what, " has ", count, " rows, fewer than one segment (",
                                    params.segment_width, " rows)"));
    }
    if (count / params.segment_width > limits.max_segments) {
        throw HttpError(413, concat(what, " has ", count / params.segment_width, " segments, more than ",
                                    limits.max_segments));
    }
    return rows_view(rows, params.channels, what, storage);
}

const json& member(const json& body, const char* key) {
    if (!body.is_object()) throw HttpError(400, "the body must be a JSON object");
    const auto it = body.find(key);
    if (it == body.end()) throw HttpError(400, concat("the body has no \"", key, "\""));
    return *it;
}

json kb_summary(const std::string& name, const fs::path& file, const kb::KnowledgeBase& base,
                const std::optional<std::uint64_t>& randomized) {
    const auto& p = base.params();
    return {{"name", name},
            {"file", file.filename().string()},
            {"segment_width", p.segment_width},
            {"channels", p.channels},
            {"delta", p.delta},
            {"match", db::to_string(p.match)},
            {"counting", kb::to_string(p.counting)},
            {"segments", base.size()},
            {"max_average_reward", base.max_average()},
            {"randomized_seed", randomized ? json(*randomized) : json()},
            {"sources", [&] {
                 json sources = json::array();
                 for (const auto& s : base.sources()) {
                     sources.push_back({{"run", s.run},
                                        {"first_generation", s.first_generation},
                                        {"last_generation", s.last_generation},
                                        {"policies", s.policies}});
                 }
                 return sources;
             }()}};
}

}  // namespace

KbService::KbService(const fs::path& input, bool writable, Limits limits)
    : input_(input), writable_(writable), limits_(limits) {
    std::error_code error;
    if (!fs::exists(input, error)) throw ConfigError(concat(input.string(), ": no such file or directory"));
    campaign_ = fs::is_directory(input);
    if (campaign_ && !fs::exists(input / "campaign.db")) {
        throw DataError(concat(input.string(),
                               ": no campaign.db here (serve a KB or run file, or a campaign directory)"));
    }
    for (const auto& wanted : wanted_kbs()) {
        if (fs::exists(wanted.file)) kbs_.push_back(load(wanted));  // else its KB step has not run yet
    }
    last_scan_ = std::chrono::steady_clock::now();
}

std::vector<KbService::WantedKb> KbService::wanted_kbs() const {
    std::vector<WantedKb> wanted;
    if (campaign_) {
        auto connection = db::open_database(input_ / "campaign.db", db::OpenMode::read_only);
        for (const auto& k : runs::load_campaign_kbs(connection))
            wanted.push_back({k.name, input_ / k.file, ""});
    } else {
        auto connection = db::open_database(input_, db::OpenMode::read_only);
        for (const auto& summary : db::list_kbs(connection))
            wanted.push_back({summary.name, input_, summary.name});
    }
    return wanted;
}

std::unique_ptr<KbService::Kb> KbService::load(const WantedKb& wanted) const {
    auto kb = std::make_unique<Kb>();
    auto connection =
        db::open_database(wanted.file, writable_ ? db::OpenMode::read_write : db::OpenMode::read_only);
    auto stored = db::load_kb(connection, wanted.stored_name);
    kb->name = wanted.name;
    kb->stored_name = stored.name;
    kb->file = wanted.file;
    kb->id = stored.id;
    kb->randomized_seed = stored.randomized_seed;
    kb->kb = std::move(stored.kb);
    if (writable_) {
        db::start_writing(connection);
        kb->writer.emplace(std::move(connection));
    }
    return kb;
}

void KbService::rescan() const {
    const auto now = std::chrono::steady_clock::now();
    {
        std::lock_guard lock(scan_mutex_);
        if (now - last_scan_ < kRescanInterval) return;
        last_scan_ = now;
    }
    // KBs that a campaign made since (or whose file was still being written): loaded now, or at a
    // later scan if they cannot be read yet
    try {
        for (const auto& wanted : wanted_kbs()) {
            {
                std::shared_lock lock(kbs_mutex_);
                if (std::any_of(kbs_.begin(), kbs_.end(),
                                [&](const auto& kb) { return kb->name == wanted.name; }))
                    continue;
            }
            if (!fs::exists(wanted.file)) continue;
            try {
                auto kb = load(wanted);
                std::unique_lock lock(kbs_mutex_);
                if (std::none_of(kbs_.begin(), kbs_.end(),
                                 [&](const auto& k) { return k->name == wanted.name; }))
                    kbs_.push_back(std::move(kb));
            } catch (const Error&) {
            }
        }
    } catch (const Error&) {
        // the index cannot be read now (being written, or gone): the KBs loaded are served
    }
}

KbService::~KbService() {
    // back to a rollback journal: later readers of the file leave no -wal or -shm beside it
    for (const auto& kb : kbs_)
        if (kb->writer) db::finish_writing(*kb->writer);
}

KbService::Kb& KbService::find(const std::string& name) const {
    rescan();
    std::shared_lock lock(kbs_mutex_);
    for (const auto& kb : kbs_) {
        if (kb->name == name) return *kb;
    }
    throw HttpError(404, concat("no knowledge base \"", name, "\" here"));
}

json KbService::list_kbs() const {
    rescan();
    json out = json::array();
    std::shared_lock list_lock(kbs_mutex_);
    for (const auto& kb : kbs_) {
        std::shared_lock lock(kb->mutex);
        auto summary = kb_summary(kb->name, kb->file, kb->kb, kb->randomized_seed);
        summary.erase("sources");
        out.push_back(summary);
    }
    return out;
}

json KbService::kb_info(const std::string& name) const {
    const Kb& kb = find(name);
    std::shared_lock lock(kb.mutex);
    auto out = kb_summary(kb.name, kb.file, kb.kb, kb.randomized_seed);
    const auto stats = runs::compute_kb_stats(kb.kb, 20);
    json bins = json::array();
    for (const auto& bin : stats.histogram) bins.push_back({{"low", bin.low}, {"high", bin.high}, {"segments", bin.segments}});
    out["histogram"] = bins;
    out["observations"] = stats.observations;
    out["segments_seen_once"] = stats.count_one;
    return out;
}

json KbService::lookup(const std::string& name, json body) const {
    const Kb& kb = find(name);
    const auto& rows = member(body, "segments");
    // an array, or a matrix packed while parsing (service/body.hpp)
    const std::size_t count = row_count(rows);
    if (!rows.is_array() && count == 0) throw HttpError(400, "\"segments\" must be an array of segments");
    if (count > limits_.max_segments) {
        throw HttpError(413,
                        concat("\"segments\" has ", count, " segments, more than ", limits_.max_segments));
    }
    const std::size_t dim = kb.kb.params().dim();
    // the packed numbers are read where they lie: the DOM is the request's only copy of them
    std::vector<float> storage;
    const auto values = rows_view(rows, dim, "segments", storage);
    std::shared_lock lock(kb.mutex);
    const auto result = kb.kb.lookup(kb::as_segments(values, dim));
    body = json();  // the numbers looked up: their DOM freed before the answer's is built
    json matches = json::array();
    for (std::size_t i = 0; i < result.segments.size(); ++i) matches.push_back(match_json(i, result.segments[i]));
    return {{"kb", kb.name}, {"match", db::to_string(kb.kb.params().match)}, {"matches", matches}, {"r_max", result.r_max}};
}

json KbService::shape(const std::string& name, json body) const {
    const Kb& kb = find(name);
    const auto& params = kb.kb.params();
    std::vector<float> storage;
    const auto values = read_behaviour(member(body, "behaviour"), params, "behaviour", limits_, storage);
    std::shared_lock lock(kb.mutex);
    const auto result = kb.kb.lookup(kb::segment_behaviour(values, params.channels, params.segment_width));
    body = json();  // the numbers looked up: their DOM freed before the answer's is built
    json matches = json::array();
    for (std::size_t i = 0; i < result.segments.size(); ++i) {
        auto m = match_json(i, result.segments[i]);
        m["step_start"] = i * params.segment_width;
        matches.push_back(m);
    }
    return {{"kb", kb.name},
            {"segment_width", params.segment_width},
            {"match", db::to_string(params.match)},
            {"max_average_reward", kb.kb.max_average()},
            {"matches", matches},
            {"r_max", result.r_max}};
}

json KbService::segments(const std::string& name, const std::string& order, std::size_t limit,
                         std::uint64_t min_count, bool values) const {
    const Kb& kb = find(name);
    if (order != "reward" && order != "count" && order != "id") {
        throw HttpError(400, concat("order must be reward, count or id, got \"", order, '"'));
    }
    if (limit > limits_.max_listed) throw HttpError(413, concat("limit must be at most ", limits_.max_listed));
    std::shared_lock lock(kb.mutex);
    const auto records = kb.kb.records();
    std::vector<std::size_t> ids;
    for (std::size_t id = 0; id < records.size(); ++id) {
        if (records[id].count >= min_count) ids.push_back(id);
    }
    // ties by id, so the order is always the same
    if (order == "reward") {
        std::stable_sort(ids.begin(), ids.end(),
                         [&](std::size_t a, std::size_t b) { return records[a].average() > records[b].average(); });
    } else if (order == "count") {
        std::stable_sort(ids.begin(), ids.end(),
                         [&](std::size_t a, std::size_t b) { return records[a].count > records[b].count; });
    }
    json out = json::array();
    for (std::size_t k = 0; k < ids.size() && k < limit; ++k) {
        const auto& r = records[ids[k]];
        json row{{"id", ids[k]},
                 {"average_reward", r.average()},
                 {"cum_reward", r.cum_reward},
                 {"count", r.count},
                 {"first_generation", r.first.generation},
                 {"last_generation", r.last.generation}};
        if (values) {
            const auto v = kb.kb.segment(ids[k]);
            row["values"] = std::vector<float>(v.begin(), v.end());
        }
        out.push_back(row);
    }
    return {{"kb", kb.name}, {"order", order}, {"matching", ids.size()}, {"segments", out}};
}

json KbService::observe(const std::string& name, const json& body) {
    if (!writable_) throw HttpError(403, "this server is read-only (its operator did not allow writes)");
    Kb& kb = find(name);
    const auto& policies = member(body, "policies");
    if (!policies.is_array() || policies.empty()) throw HttpError(400, "\"policies\" must be a non-empty array");
    if (policies.size() > limits_.max_policies) {
        throw HttpError(413, concat("\"policies\" has ", policies.size(), " policies, more than ", limits_.max_policies));
    }
    std::string run = "service";
    if (body.contains("run")) {
        if (!body["run"].is_string()) throw HttpError(400, "\"run\" must be a string");
        run = body["run"].get<std::string>();
        try {
            kb::check_run_name(run, "\"run\"");
        } catch (const DataError& e) {
            throw HttpError(400, e.what());
        }
    }
    std::int64_t generation = 0;
    if (body.contains("generation")) {
        if (!body["generation"].is_number_integer() || body["generation"].get<std::int64_t>() < 0) {
            throw HttpError(400, "\"generation\" must be a whole number >= 0");
        }
        generation = body["generation"].get<std::int64_t>();
    }
    // every policy checked before any is observed
    const auto& params = kb.kb.params();
    std::vector<std::span<const float>> behaviours;
    std::vector<std::vector<float>> storage(policies.size());  // the behaviours that were not packed
    std::vector<double> rewards;
    for (std::size_t i = 0; i < policies.size(); ++i) {
        const auto& p = policies[i];
        const auto what = concat("policies[", i, "]");
        if (!p.is_object() || !p.contains("behaviour") || !p.contains("reward")) {
            throw HttpError(400, what + " must be an object with \"behaviour\" and \"reward\"");
        }
        if (!p["reward"].is_number() || !std::isfinite(p["reward"].get<double>()) ||
            std::abs(p["reward"].get<double>()) > kb::kMaxRewardMagnitude) {
            throw HttpError(400, concat(what, ".reward must be a finite number within +-",
                                        shortest(kb::kMaxRewardMagnitude)));
        }
        behaviours.push_back(
            read_behaviour(p["behaviour"], params, what + ".behaviour", limits_, storage[i]));
        rewards.push_back(p["reward"].get<double>());
    }
    std::unique_lock lock(kb.mutex);
    const std::size_t previous = kb.kb.size();
    std::size_t inserted = 0, matched = 0;
    try {
        const auto source = kb.kb.add_source(run);
        for (std::size_t i = 0; i < behaviours.size(); ++i) {
            const auto result = kb.kb.observe(
                kb::segment_behaviour(behaviours[i], params.channels, params.segment_width), rewards[i],
                {source, generation});
            inserted += result.inserted;
            matched += result.matched;
        }
        db::Transaction transaction(*kb.writer);
        db::update_kb(*kb.writer, kb.id, kb.kb, previous, generation);
        transaction.commit();
    } catch (...) {
        // the transaction rolled back: the KB is again what the file holds
        kb.kb = db::load_kb(*kb.writer, kb.stored_name).kb;
        throw;
    }
    return {{"kb", kb.name},      {"observed", behaviours.size()}, {"inserted", inserted},
            {"matched", matched}, {"segments", kb.kb.size()},       {"durable", true}};
}

bool KbService::run_started(std::int64_t id) const {
    for (const auto& r : runs::load_campaign(input_).runs) {
        if (r.id == id) return r.status != runs::RunStatus::pending;
    }
    return false;
}

std::vector<KbService::RunFile> KbService::run_files() const {
    std::vector<RunFile> out;
    const auto index = campaign_ ? input_ / "campaign.db" : input_;
    if (!fs::exists(index)) {
        throw HttpError(410, concat(index.filename().string(), " is gone (deleted while served)"));
    }
    if (!campaign_) {
        auto connection = db::open_database(input_, db::OpenMode::read_only);
        if (runs::holds_run(connection)) out.push_back({1, input_});
        return out;
    }
    for (const auto& r : runs::load_campaign(input_).runs) out.push_back({r.id, input_ / r.run.file});
    return out;
}

json KbService::runs() const {
    json out = json::array();
    if (campaign_) {
        for (const auto& r : runs::load_campaign(input_).runs) {
            out.push_back({{"id", r.id},
                           {"step", runs::to_string(r.run.step)},
                           {"treatment", runs::to_string(r.run.treatment)},
                           {"seed", r.run.seed},
                           {"file", r.run.file},
                           {"generations", r.run.generations},
                           {"status", runs::to_string(r.status)},
                           {"generations_done", r.generations_done},
                           {"best_reward", r.best_reward ? json(*r.best_reward) : json()}});
        }
        return out;
    }
    for (const auto& file : run_files()) {
        auto connection = db::open_database(file.path, db::OpenMode::read_only);
        const auto run = runs::load_run(connection);
        const auto best = runs::best_reward(connection);
        out.push_back({{"id", file.id},
                       {"step", run.task},
                       {"treatment", run.treatment},
                       {"seed", run.seed},
                       {"file", file.path.filename().string()},
                       {"generations", run.generations},
                       {"status", runs::to_string(run.status)},
                       {"generations_done", run.generations_done},
                       {"best_reward", best ? json(*best) : json()}});
    }
    return out;
}

json KbService::generations(std::int64_t id) const {
    for (const auto& file : run_files()) {
        if (file.id != id) continue;
        json out = json::array();
        if (!fs::exists(file.path)) {
            if (!campaign_ || run_started(id)) {
                throw HttpError(410, concat("run ", id, ": its file ", file.path.filename().string(),
                                            " is gone (deleted while served)"));
            }
            return out;  // not started yet
        }
        auto connection = db::open_database(file.path, db::OpenMode::read_only);
        for (const auto& g : runs::load_generations(connection, runs::load_run(connection).id)) {
            out.push_back({{"generation", g.generation},
                           {"best_reward", g.best},
                           {"median_reward", g.median},
                           {"mean_r_max", g.mean_r_max ? json(*g.mean_r_max) : json()},
                           {"max_r_max", g.max_r_max ? json(*g.max_r_max) : json()}});
        }
        return out;
    }
    throw HttpError(404, concat("no run ", id, " here"));
}

json KbService::campaign() const {
    if (!campaign_) throw HttpError(404, "not serving a campaign directory");
    const auto index = runs::load_campaign(input_);
    json by_status = json::object();
    for (const auto& entry : index.runs) {
        const std::string status(runs::to_string(entry.status));
        by_status[status] = by_status.value(status, 0) + 1;
    }
    rescan();
    json kbs = json::array();
    std::shared_lock lock(kbs_mutex_);
    for (const auto& kb : kbs_) kbs.push_back(kb->name);
    return {{"directory", input_.filename().string()}, {"config", index.config}, {"runs", by_status}, {"kbs", kbs}};
}

}  // namespace stepstone::service
