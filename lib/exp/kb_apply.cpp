#include "exp/kb_apply.hpp"

#include <algorithm>
#include <cstring>
#include <optional>

#include "core/text.hpp"
#include "db/database.hpp"
#include "db/kb_store.hpp"
#include "evo/pareto.hpp"
#include "exp/parallel/writer_lock.hpp"
#include "kb/segments.hpp"
#include "runs/kb_files.hpp"
#include "runs/replay.hpp"
#include "runs/run_store.hpp"
#include "sim/sensors.hpp"

namespace stepstone::exp {

namespace fs = std::filesystem;

namespace {

// the first front of the last checkpointed population, restricted to stored genomes
std::vector<std::int64_t> front_individuals(db::Connection& connection, std::int64_t run_id) {
    const auto checkpoint = runs::load_checkpoint(connection, run_id);
    if (!checkpoint)
        throw DataError(concat(connection.name(), ": run ", run_id, " has no committed generation"));
    std::vector<std::int64_t> ids;
    evo::Objectives objectives;
    try {
        for (const auto& member : checkpoint->at("population")) {
            ids.push_back(member.at("id").get<std::int64_t>());
            objectives.push_back(member.at("objectives").get<std::vector<double>>());
        }
    } catch (const nlohmann::json::exception& e) {
        throw DatabaseError(
            concat(connection.name(), ": run ", run_id, " has a malformed checkpoint: ", one_line(e.what())));
    }
    const auto stored = runs::stored_individuals(connection, run_id);
    std::vector<std::int64_t> front;
    const auto fronts = evo::non_dominated_fronts(objectives);
    if (fronts.empty())
        throw DataError(concat(connection.name(), ": run ", run_id, " has an empty checkpoint population"));
    for (std::size_t k : fronts.front()) {
        if (std::binary_search(stored.begin(), stored.end(), ids[k])) front.push_back(ids[k]);
    }
    std::sort(front.begin(), front.end());
    if (front.empty())
        throw DataError(concat(connection.name(), ": no genome of the last first front is stored"));
    return front;
}

std::vector<std::int64_t> select_individuals(const fs::path& run_db, PolicySet which) {
    auto connection = db::open_database(run_db, db::OpenMode::read_only);
    const runs::RunRecord run = runs::load_run(connection);
    switch (which) {
        case PolicySet::best:
            return {runs::load_best_genome(connection, run.id).individual_id};
        case PolicySet::front:
            return front_individuals(connection, run.id);
        case PolicySet::all:
            break;
    }
    auto ids = runs::stored_individuals(connection, run.id);
    if (ids.empty()) throw DataError(concat(run_db.string(), ": run ", run.id, " has no stored genome"));
    return ids;
}

// a KB is applicable to a run's behaviours when it has their channels and
// its segments fit in them
void check_kb_fits(const kb::KbParams& params, const std::string& kb_what, std::size_t steps,
                   const std::string& run_file) {
    const auto channels = static_cast<std::size_t>(sim::kChannels);
    if (params.channels != channels) {
        throw DataError(concat(kb_what, " has ", params.channels, " channels, the behaviours of ", run_file,
                               " have ", channels));
    }
    if (params.segment_width > steps) {
        throw DataError(concat(kb_what, " has segment_width ", params.segment_width, ", the behaviours of ",
                               run_file, " last ", steps, " steps"));
    }
}

bool same_kb(const kb::KnowledgeBase& a, const kb::KnowledgeBase& b) {
    const auto& pa = a.params();
    const auto& pb = b.params();
    if (pa.segment_width != pb.segment_width || pa.channels != pb.channels || pa.delta != pb.delta ||
        pa.match != pb.match || a.size() != b.size()) {
        return false;
    }
    for (std::size_t i = 0; i < a.size(); ++i) {
        if (a.record(i).cum_reward != b.record(i).cum_reward || a.record(i).count != b.record(i).count)
            return false;
    }
    const auto va = a.values();
    const auto vb = b.values();
    return std::memcmp(va.data(), vb.data(), va.size_bytes()) == 0;
}

}  // namespace

PolicySet parse_policy_set(const std::string& text, const std::string& what) {
    if (text == "best") return PolicySet::best;
    if (text == "front") return PolicySet::front;
    if (text == "all") return PolicySet::all;
    throw ConfigError(concat(what, " must be one of best|front|all, got \"", text, '"'));
}

Annotation annotate_run(const fs::path& run_db, const fs::path& kb_db, PolicySet which,
                        const std::string& kb_name, const std::string& as_name) {
    const auto stored = runs::load_kb_file(kb_db, kb_name);
    const std::string kb_what = concat(kb_db.string(), ": knowledge base \"", stored.name, '"');
    Annotation result;
    result.kb_name = as_name.empty() ? stored.name : as_name;
    result.individuals = select_individuals(run_db, which);

    // every replay and lookup happens before the run file is opened for writing
    std::vector<kb::Lookup> lookups;
    for (std::int64_t id : result.individuals) {
        const auto behaviour = runs::replay_behaviour(run_db, std::to_string(id));
        const auto channels = static_cast<std::size_t>(sim::kChannels);
        check_kb_fits(stored.kb.params(), kb_what, behaviour.size() / channels, run_db.string());
        lookups.push_back(
            stored.kb.lookup(kb::segment_behaviour(behaviour, channels, stored.kb.params().segment_width)));
    }

    const WriterLock lock(run_db);  // not while evolve writes the run
    auto connection = db::open_database(run_db, db::OpenMode::read_write);
    const runs::RunRecord run = runs::load_run(connection);
    db::Transaction transaction(connection);
    // the KB the rows refer to lives in the run file itself
    std::optional<std::int64_t> existing;
    for (const auto& summary : db::list_kbs(connection)) {
        if (summary.name == result.kb_name) existing = summary.id;
    }
    if (existing) {
        if (!same_kb(db::load_kb(connection, result.kb_name).kb, stored.kb)) {
            throw KbNameTaken(concat(run_db.string(), ": already holds a different knowledge base named \"",
                                     result.kb_name, '"'));
        }
        result.kb_id = *existing;
    } else {
        result.kb_id = db::insert_kb(connection, result.kb_name, stored.kb, stored.randomized_seed);
        result.copied = true;
    }

    auto insert = connection.prepare(db::sql("kb/insert_policy_segment.sql"));
    for (std::size_t p = 0; p < result.individuals.size(); ++p) {
        const auto& segments = lookups[p].segments;
        for (std::size_t s = 0; s < segments.size(); ++s) {
            insert.reset();
            std::optional<std::int64_t> kb_segment_id;
            if (segments[s].id) kb_segment_id = static_cast<std::int64_t>(*segments[s].id);
            insert.bind(":run_id", run.id)
                .bind(":individual_id", result.individuals[p])
                .bind(":kb_id", result.kb_id)
                .bind(":segment", static_cast<std::int64_t>(s))
                .bind(":kb_segment_id", kb_segment_id)
                .bind(":distance", segments[s].distance)
                .bind(":average_reward", segments[s].average_reward)
                .run();
            ++result.rows;
        }
    }
    transaction.commit();
    return result;
}

Shaping shape_policy(const fs::path& kb_db, const fs::path& run_db, const std::string& individual,
                     const std::string& kb_name) {
    const auto stored = runs::load_kb_file(kb_db, kb_name);
    runs::Replay replayed;
    const auto behaviour = replay_behaviour(run_db, individual, &replayed);
    const auto channels = static_cast<std::size_t>(sim::kChannels);
    check_kb_fits(stored.kb.params(), concat(kb_db.string(), ": knowledge base \"", stored.name, '"'),
                  behaviour.size() / channels, run_db.string());
    const auto lookup =
        stored.kb.lookup(kb::segment_behaviour(behaviour, channels, stored.kb.params().segment_width));

    Shaping shaping;
    shaping.individual_id = replayed.individual_id;
    shaping.generation = replayed.generation;
    shaping.stored_reward = replayed.stored_reward;
    shaping.kb_name = stored.name;
    shaping.params = stored.kb.params();
    shaping.max_average = stored.kb.max_average();
    shaping.r_max = lookup.r_max;
    shaping.segments = lookup.segments;
    return shaping;
}
}  // namespace stepstone::exp
