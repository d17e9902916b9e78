#include "exp/kb_tools.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <iomanip>
#include <numeric>
#include <sstream>

#include "core/error.hpp"
#include "core/writer_lock.hpp"
#include "core/text.hpp"
#include "db/database.hpp"
#include "db/kb_store.hpp"
#include "evo/pareto.hpp"
#include "exp/evaluation.hpp"
#include "exp/evolve_config.hpp"
#include "exp/kb_duplicates.hpp"
#include "exp/replay.hpp"
#include "exp/run_store.hpp"
#include "kb/segments.hpp"
#include "nn/genome.hpp"
#include "sim/task.hpp"
#include "sim/sensors.hpp"

namespace stepstone::exp {

namespace fs = std::filesystem;

namespace {

std::string file_name(const fs::path& path) { return path.string(); }

KbWritten written(const std::string& name, const kb::KnowledgeBase& kb, std::optional<std::uint64_t> seed) {
    return {name, kb.params(), kb.size(), seed};
}

// writes one KB as the only content of a new file, atomically
void write_kb_file(const fs::path& out, bool force, const std::string& name, const kb::KnowledgeBase& kb,
                   std::optional<std::uint64_t> seed) {
    db::OutputDatabase output(out, force);
    {
        db::Transaction transaction(output.connection());
        db::insert_kb(output.connection(), name, kb, seed);
        transaction.commit();
    }
    output.commit();
}

db::StoredKb load_kb_file(const fs::path& path, const std::string& name) {
    auto connection = db::open_database(path, db::OpenMode::read_only);
    return db::load_kb(connection, name);
}

// the first parameter in which two KBs differ, named as the CLI and config do
std::optional<std::string> params_mismatch(const kb::KbParams& a, const kb::KbParams& b,
                                           const std::string& a_name, const std::string& b_name) {
    if (a.segment_width != b.segment_width) {
        return concat("segment_width is ", b.segment_width, " in ", b_name, ", ", a.segment_width, " in ",
                      a_name);
    }
    if (a.channels != b.channels) {
        return concat("channels is ", b.channels, " in ", b_name, ", ", a.channels, " in ", a_name);
    }
    if (a.delta != b.delta) {
        return concat("delta is ", shortest(b.delta), " in ", b_name, ", ", shortest(a.delta), " in ", a_name);
    }
    return std::nullopt;
}

// the ids of the run's stored genomes, in increasing order
std::vector<std::int64_t> stored_individuals(db::Connection& connection, std::int64_t run_id) {
    auto select =
        connection.prepare("SELECT individual_id FROM genome WHERE run_id = ?1 ORDER BY individual_id");
    select.bind(1, run_id);
    std::vector<std::int64_t> ids;
    while (select.step()) ids.push_back(select.column_int(0));
    return ids;
}

// the first front of the last checkpointed population, restricted to stored genomes
std::vector<std::int64_t> front_individuals(db::Connection& connection, std::int64_t run_id) {
    const auto checkpoint = load_checkpoint(connection, run_id);
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
    const auto stored = stored_individuals(connection, run_id);
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
    const RunRecord run = load_run(connection);
    switch (which) {
        case PolicySet::best:
            return {load_best_genome(connection, run.id).individual_id};
        case PolicySet::front:
            return front_individuals(connection, run.id);
        case PolicySet::all:
            break;
    }
    auto ids = stored_individuals(connection, run.id);
    if (ids.empty()) throw DataError(concat(file_name(run_db), ": run ", run.id, " has no stored genome"));
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

double median_of(std::vector<std::uint64_t> values) {
    if (values.empty()) return 0.0;
    std::sort(values.begin(), values.end());
    const std::size_t n = values.size();
    return n % 2 == 1 ? static_cast<double>(values[n / 2])
                      : 0.5 * (static_cast<double>(values[n / 2 - 1]) + static_cast<double>(values[n / 2]));
}

std::string optional_seed_text(const std::optional<std::uint64_t>& seed) {
    return seed ? concat(*seed) : std::string("none");
}

}  // namespace

// ------------------------------------------------------------ export, merge, randomize

KbWritten export_kb(const fs::path& run_db, const std::string& name, const fs::path& out, bool force,
                    std::optional<double> delta) {
    db::check_output_path(out, force);
    const auto stored = load_kb_file(run_db, name);
    if (!delta) {
        write_kb_file(out, force, stored.name, stored.kb, stored.randomized_seed);
        return written(stored.name, stored.kb, stored.randomized_seed);
    }
    if (stored.randomized_seed) {
        throw DataError(concat(file_name(run_db), ": \"", stored.name,
                               "\" is randomized; coarsen the real KB, then randomize it"));
    }
    const kb::KnowledgeBase coarse = stored.kb.coarsened(*delta);
    write_kb_file(out, force, stored.name, coarse, std::nullopt);
    return written(stored.name, coarse, std::nullopt);
}

KbWritten merge_kb_files(std::span<const fs::path> inputs, const fs::path& out, const std::string& name,
                         bool force, const std::string& input_name, bool allow_duplicates) {
    if (inputs.size() < 2)
        throw ConfigError(concat("kb merge needs at least two KB files, got ", inputs.size()));
    db::check_output_path(out, force);
    // every input is loaded and checked before the output is created
    std::vector<db::StoredKb> loaded;
    for (const auto& path : inputs) loaded.push_back(load_kb_file(path, input_name));
    const std::string first = file_name(inputs[0]);
    for (std::size_t i = 1; i < loaded.size(); ++i) {
        if (auto mismatch =
                params_mismatch(loaded[0].kb.params(), loaded[i].kb.params(), first, file_name(inputs[i]))) {
            throw DataError(concat("cannot merge ", file_name(inputs[i]), " into ", first, ": ", *mismatch));
        }
    }
    if (!allow_duplicates) refuse_duplicate_kbs(inputs, loaded);
    kb::KnowledgeBase merged = std::move(loaded[0].kb);
    for (std::size_t i = 1; i < loaded.size(); ++i) merged.merge(loaded[i].kb);
    const std::string out_name = name.empty() ? loaded[0].name : name;
    write_kb_file(out, force, out_name, merged, std::nullopt);
    return written(out_name, merged, std::nullopt);
}

KbWritten randomize_kb_file(const fs::path& in, const fs::path& out, std::uint64_t seed,
                            const std::string& name, bool force, const std::string& input_name) {
    db::check_output_path(out, force);
    const auto stored = load_kb_file(in, input_name);
    const kb::KnowledgeBase randomized = stored.kb.randomized(seed);
    const std::string out_name = name.empty() ? stored.name + "-rand" : name;
    write_kb_file(out, force, out_name, randomized, seed);
    return written(out_name, randomized, seed);
}

// -------------------------------------------------------------------- calibrate

std::vector<double> parse_deltas(const std::string& text, const std::string& what) {
    std::vector<double> deltas;
    std::size_t start = 0;
    while (start <= text.size()) {
        const std::size_t comma = std::min(text.find(',', start), text.size());
        const std::string item = text.substr(start, comma - start);
        double value = 0.0;
        const auto parsed = std::from_chars(item.data(), item.data() + item.size(), value);
        if (item.empty() || parsed.ec != std::errc() || parsed.ptr != item.data() + item.size() ||
            !std::isfinite(value) || value <= 0.0) {
            throw ConfigError(
                concat(what, " must be a comma-separated list of numbers > 0, got \"", text, '"'));
        }
        deltas.push_back(value);
        start = comma + 1;
    }
    return deltas;
}

Calibration calibrate_behaviours(std::span<const float> policy, std::span<const std::vector<float>> policies,
                                 std::size_t channels, std::size_t segment_width,
                                 std::span<const double> deltas, std::size_t neighbours) {
    Calibration result;
    result.segment_width = segment_width;
    result.channels = channels;
    result.neighbours = neighbours;
    const kb::Segments own = kb::segment_behaviour(policy, channels, segment_width);
    result.segments = own.size();
    result.delta = kb::calibrate_delta(own, neighbours);

    std::vector<kb::Segments> segmented;
    for (const auto& behaviour : policies)
        segmented.push_back(kb::segment_behaviour(behaviour, channels, segment_width));
    result.policies = segmented.size();
    if (!deltas.empty()) {
        kb::KbParams params;
        params.segment_width = segment_width;
        params.channels = channels;
        result.sizes = kb::kb_sizes(params, segmented, deltas);
    }
    return result;
}

RunCalibration calibrate_run(const fs::path& run_db, const CalibrateOptions& options) {
    if (options.batch == 0) throw ConfigError("calibrate: the batch must hold at least one policy");
    RunCalibration out;
    std::size_t width = 20;
    out.width_from = "default";
    std::vector<std::int64_t> ids;
    auto connection = db::open_database(run_db, db::OpenMode::read_only);
    const RunRecord run = load_run(connection);
    for (const auto& summary : db::list_kbs(connection)) {
        if (summary.name == kRunKbName) {
            width = summary.params.segment_width;
            out.width_from = "the run's knowledge base";
        }
    }
    ids = stored_individuals(connection, run.id);
    if (options.segment_width) {
        if (*options.segment_width == 0) throw ConfigError("--segment-width must be >= 1, got 0");
        width = *options.segment_width;
        out.width_from = "--segment-width";
    }

    Replay replayed;
    const auto best = replay_behaviour(run_db, options.individual, &replayed);
    out.individual_id = replayed.individual_id;
    out.reward = replayed.stored_reward;
    const auto channels = static_cast<std::size_t>(sim::kChannels);
    if (width > best.size() / channels) {
        throw ConfigError(concat("--segment-width ", width, " exceeds the ", best.size() / channels,
                                 " steps of the behaviours of ", file_name(run_db)));
    }
    out.calibration = calibrate_behaviours(best, {}, channels, width, {}, options.neighbours);
    if (options.deltas.empty()) return out;

    // the size table: one KB per delta, fed batch by batch in id order
    EvolveConfig config = EvolveConfig::from_json(run.config, file_name(run_db) + " (stored config)");
    config.task.starts = 1;  // the behaviour is the first start's, which later starts do not change
    const auto task = sim::make_task(config.task);
    std::vector<kb::KnowledgeBase> kbs;
    for (const double delta : options.deltas) {
        kb::KbParams params;
        params.segment_width = width;
        params.channels = channels;
        params.delta = delta;
        kbs.emplace_back(params);
        kbs.back().add_source("calibrate");
    }
    const std::size_t size = task->behaviour_size();
    Progress progress("policy", ids.size(), options.progress);
    std::vector<nn::Genome> genomes;
    std::vector<float> behaviours;
    for (std::size_t start = 0; start < ids.size(); start += options.batch) {
        const std::size_t n = std::min(options.batch, ids.size() - start);
        genomes.clear();
        for (std::size_t k = 0; k < n; ++k)
            genomes.push_back(nn::Genome::from_json(load_genome(connection, run.id, ids[start + k]).genome));
        behaviours.assign(n * size, 0.0f);
        parallel_for(n, options.threads, [&](std::size_t k) {
            evaluate_genome(*task, genomes[k], config.dnn, std::span<float>(behaviours.data() + k * size, size));
        });
        std::vector<kb::Segments> segments;
        for (std::size_t k = 0; k < n; ++k)
            segments.push_back(kb::segment_behaviour(std::span<const float>(behaviours.data() + k * size, size),
                                                     channels, width));
        parallel_for(kbs.size(), options.threads, [&](std::size_t d) {
            for (const auto& policy : segments) kbs[d].observe(policy, 0.0, kb::Origin{0, 0});
        });
        std::string status = "KB sizes";
        for (std::size_t d = 0; d < kbs.size(); ++d)
            status += concat(' ', shortest(options.deltas[d]), ':', kbs[d].size());
        progress.update(start + n, status);
    }
    progress.finish();
    out.calibration.policies = ids.size();
    for (std::size_t d = 0; d < kbs.size(); ++d) out.calibration.sizes.push_back({options.deltas[d], kbs[d].size()});
    return out;
}

// ------------------------------------------------------------------------ stats

KbStats compute_kb_stats(const kb::KnowledgeBase& kb, std::size_t bins) {
    KbStats stats;
    stats.params = kb.params();
    stats.segments = kb.size();
    stats.max_average = kb.max_average();
    stats.sources.assign(kb.sources().begin(), kb.sources().end());
    stats.bytes_per_segment = kb.bytes_per_segment();

    // histogram of the averages over [0, max] ([0, 1] when every average is 0)
    const double top = stats.max_average > 0 ? stats.max_average : 1.0;
    for (std::size_t b = 0; b < bins; ++b) {
        stats.histogram.push_back({top * static_cast<double>(b) / static_cast<double>(bins),
                                   top * static_cast<double>(b + 1) / static_cast<double>(bins), 0});
    }
    std::vector<std::uint64_t> counts;
    counts.reserve(kb.size());
    for (const auto& record : kb.records()) {
        const double scaled = std::floor(record.average() / top * static_cast<double>(bins));
        const std::size_t bin = scaled <= 0 ? 0 : std::min(bins - 1, static_cast<std::size_t>(scaled));
        if (bins > 0) ++stats.histogram[bin].segments;
        counts.push_back(record.count);
        stats.observations += record.count;
        if (record.count == 1) ++stats.count_one;
    }
    if (!counts.empty()) {
        stats.count_min = *std::min_element(counts.begin(), counts.end());
        stats.count_max = *std::max_element(counts.begin(), counts.end());
        stats.count_mean = static_cast<double>(stats.observations) / static_cast<double>(counts.size());
        stats.count_median = median_of(std::move(counts));
    }
    return stats;
}

KbStats kb_file_stats(const fs::path& kb_db, const std::string& name) {
    const auto stored = load_kb_file(kb_db, name);
    KbStats stats = compute_kb_stats(stored.kb);
    stats.file = file_name(kb_db);
    stats.name = stored.name;
    stats.randomized_seed = stored.randomized_seed;
    if (stats.segments > 0) {
        stats.file_bytes_per_segment =
            static_cast<double>(fs::file_size(kb_db)) / static_cast<double>(stats.segments);
    }
    return stats;
}

nlohmann::json to_json(const KbStats& stats) {
    nlohmann::json out;
    out["file"] = stats.file;
    out["name"] = stats.name;
    out["segments"] = stats.segments;
    out["segment_width"] = stats.params.segment_width;
    out["channels"] = stats.params.channels;
    out["delta"] = stats.params.delta;
    out["match"] = db::to_string(stats.params.match);
    out["randomized_seed"] =
        stats.randomized_seed ? nlohmann::json(*stats.randomized_seed) : nlohmann::json();
    out["max_average_reward"] = stats.max_average;
    out["histogram"] = nlohmann::json::array();
    for (const auto& bin : stats.histogram) {
        out["histogram"].push_back({{"low", bin.low}, {"high", bin.high}, {"segments", bin.segments}});
    }
    out["counts"] = {
        {"observations", stats.observations}, {"min", stats.count_min}, {"median", stats.count_median},
        {"mean", stats.count_mean},           {"max", stats.count_max}, {"seen_once", stats.count_one}};
    out["sources"] = nlohmann::json::array();
    for (const auto& source : stats.sources) {
        out["sources"].push_back({{"run", source.run},
                                  {"first_generation", source.first_generation},
                                  {"last_generation", source.last_generation},
                                  {"policies", source.policies}});
    }
    out["bytes_per_segment"] = {{"memory", stats.bytes_per_segment}, {"file", stats.file_bytes_per_segment}};
    return out;
}

void write_text(std::ostream& out, const KbStats& stats) {
    out << "knowledge base  \"" << stats.name << "\" in " << stats.file << '\n'
        << "segments        " << stats.segments << '\n'
        << "segment_width   " << stats.params.segment_width << '\n'
        << "channels        " << stats.params.channels << '\n'
        << "delta           " << stats.params.delta << '\n'
        << "match           " << db::to_string(stats.params.match) << '\n'
        << "randomized_seed " << optional_seed_text(stats.randomized_seed) << '\n'
        << "max average     " << stats.max_average << '\n';

    // the paper's Fig. 3 as text: one row per bin, bar scaled to the largest bin
    out << "\naverage reward histogram (segments per bin)\n";
    std::size_t largest = 0;
    for (const auto& bin : stats.histogram) largest = std::max(largest, bin.segments);
    for (std::size_t b = 0; b < stats.histogram.size(); ++b) {
        const auto& bin = stats.histogram[b];
        const std::size_t bar = largest == 0 ? 0 : (bin.segments * 50 + largest - 1) / largest;
        const char close = b + 1 == stats.histogram.size() ? ']' : ')';
        std::ostringstream range;
        range << std::fixed << std::setprecision(4) << '[' << bin.low << ", " << bin.high << close;
        out << "  " << std::left << std::setw(20) << range.str() << std::right << std::setw(10)
            << bin.segments << "  " << std::string(bar, '#') << '\n';
    }

    out << "\ncounts          observations " << stats.observations << ", min " << stats.count_min
        << ", median " << stats.count_median << ", mean " << stats.count_mean << ", max " << stats.count_max
        << ", seen once " << stats.count_one << '\n';
    out << "\nprovenance      " << stats.sources.size()
        << (stats.sources.size() == 1 ? " source" : " sources") << '\n';
    for (const auto& source : stats.sources) {
        out << "  " << source.run << ": generations " << source.first_generation << " to "
            << source.last_generation << ", " << source.policies << " policies\n";
    }
    out << "\nbytes/segment   " << std::fixed << std::setprecision(1) << stats.bytes_per_segment
        << " in memory, " << stats.file_bytes_per_segment << " in the file\n"
        << std::defaultfloat;
}

// --------------------------------------------------------------------- annotate

PolicySet parse_policy_set(const std::string& text) {
    if (text == "best") return PolicySet::best;
    if (text == "front") return PolicySet::front;
    if (text == "all") return PolicySet::all;
    throw ConfigError(concat("--individuals must be one of best|front|all, got \"", text, '"'));
}

Annotation annotate_run(const fs::path& run_db, const fs::path& kb_db, PolicySet which,
                        const std::string& kb_name, const std::string& as_name) {
    const auto stored = load_kb_file(kb_db, kb_name);
    const std::string kb_what = concat(file_name(kb_db), ": knowledge base \"", stored.name, '"');
    Annotation result;
    result.kb_name = as_name.empty() ? stored.name : as_name;
    result.individuals = select_individuals(run_db, which);

    // every replay and lookup happens before the run file is opened for writing
    std::vector<kb::Lookup> lookups;
    for (std::int64_t id : result.individuals) {
        const auto behaviour = replay_behaviour(run_db, std::to_string(id));
        const auto channels = static_cast<std::size_t>(sim::kChannels);
        check_kb_fits(stored.kb.params(), kb_what, behaviour.size() / channels, file_name(run_db));
        lookups.push_back(
            stored.kb.lookup(kb::segment_behaviour(behaviour, channels, stored.kb.params().segment_width)));
    }

    const WriterLock lock(run_db);  // not while evolve writes the run
    auto connection = db::open_database(run_db, db::OpenMode::read_write);
    const RunRecord run = load_run(connection);
    db::Transaction transaction(connection);
    // the KB the rows refer to lives in the run file itself
    std::optional<std::int64_t> existing;
    for (const auto& summary : db::list_kbs(connection)) {
        if (summary.name == result.kb_name) existing = summary.id;
    }
    if (existing) {
        if (!same_kb(db::load_kb(connection, result.kb_name).kb, stored.kb)) {
            throw DataError(concat(file_name(run_db), ": already holds a different knowledge base named \"",
                                   result.kb_name, "\"; choose another name with --as"));
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
            insert.bind(1, run.id)
                .bind(2, result.individuals[p])
                .bind(3, result.kb_id)
                .bind(4, static_cast<std::int64_t>(s));
            if (segments[s].id) {
                insert.bind(5, static_cast<std::int64_t>(*segments[s].id));
            } else {
                insert.bind_null(5);
            }
            insert.bind(6, segments[s].distance).bind(7, segments[s].average_reward).run();
            ++result.rows;
        }
    }
    transaction.commit();
    return result;
}

// ------------------------------------------------------------------------ shape

Shaping shape_policy(const fs::path& kb_db, const fs::path& run_db, const std::string& individual,
                     const std::string& kb_name) {
    const auto stored = load_kb_file(kb_db, kb_name);
    Replay replayed;
    const auto behaviour = replay_behaviour(run_db, individual, &replayed);
    const auto channels = static_cast<std::size_t>(sim::kChannels);
    check_kb_fits(stored.kb.params(), concat(file_name(kb_db), ": knowledge base \"", stored.name, '"'),
                  behaviour.size() / channels, file_name(run_db));
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

nlohmann::json to_json(const Shaping& shaping) {
    nlohmann::json out;
    out["individual_id"] = shaping.individual_id;
    out["generation"] = shaping.generation;
    out["stored_reward"] = shaping.stored_reward;
    out["kb"] = {{"name", shaping.kb_name},
                 {"segment_width", shaping.params.segment_width},
                 {"channels", shaping.params.channels},
                 {"delta", shaping.params.delta},
                 {"match", db::to_string(shaping.params.match)},
                 {"max_average_reward", shaping.max_average}};
    out["r_max"] = shaping.r_max;
    out["segments"] = nlohmann::json::array();
    const auto width = static_cast<std::int64_t>(shaping.params.segment_width);
    for (std::size_t s = 0; s < shaping.segments.size(); ++s) {
        const auto& match = shaping.segments[s];
        const auto start = static_cast<std::int64_t>(s) * width;
        out["segments"].push_back({{"segment", s},
                                   {"step_start", start},
                                   {"step_end", start + width},
                                   {"kb_segment_id", match.id ? nlohmann::json(*match.id) : nlohmann::json()},
                                   {"distance", match.distance},
                                   {"average_reward", match.average_reward}});
    }
    return out;
}

void write_text(std::ostream& out, const Shaping& shaping) {
    out << "individual " << shaping.individual_id << " (generation " << shaping.generation
        << "), stored reward " << shaping.stored_reward << '\n'
        << "knowledge base \"" << shaping.kb_name << "\": segment_width " << shaping.params.segment_width
        << ", channels " << shaping.params.channels << ", delta " << shaping.params.delta << ", match "
        << db::to_string(shaping.params.match) << ", max average " << shaping.max_average << '\n'
        << "r_max " << shaping.r_max << '\n'
        << "segment  steps          kb_segment  distance    average_reward\n";
    const std::size_t width = shaping.params.segment_width;
    for (std::size_t s = 0; s < shaping.segments.size(); ++s) {
        const auto& match = shaping.segments[s];
        out << std::left << std::setw(9) << s << std::setw(15) << concat(s * width, '-', (s + 1) * width)
            << std::setw(12) << (match.id ? concat(*match.id) : std::string("none")) << std::setw(12)
            << concat(std::setprecision(6), match.distance)
            << concat(std::setprecision(6), match.average_reward) << std::right << '\n';
    }
}

}  // namespace stepstone::exp
