#include "exp/kb_calibrate.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>

#include "core/error.hpp"
#include "core/text.hpp"
#include "db/database.hpp"
#include "db/kb_store.hpp"
#include "exp/evaluation.hpp"
#include "kb/segments.hpp"
#include "nn/genome.hpp"
#include "runs/evolve_config.hpp"
#include "runs/replay.hpp"
#include "runs/run_store.hpp"
#include "sim/sensors.hpp"
#include "sim/task.hpp"

namespace stepstone::exp {

namespace fs = std::filesystem;

const char* to_string(DeltaReading reading) {
    return reading == DeltaReading::windows ? "windows" : "segments";
}

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
    std::size_t width = kb::kDefaultSegmentWidth;
    out.width_from = WidthSource::default_width;
    std::vector<std::int64_t> ids;
    auto connection = db::open_database(run_db, db::OpenMode::read_only);
    const runs::RunRecord run = runs::load_run(connection);
    for (const auto& summary : db::list_kbs(connection)) {
        if (summary.name == runs::kRunKbName) {
            width = summary.params.segment_width;
            out.width_from = WidthSource::run_kb;
        }
    }
    ids = runs::stored_individuals(connection, run.id);
    if (options.segment_width) {
        if (*options.segment_width == 0)
            throw ConfigError(concat(options.width_name, " must be >= 1, got 0"));
        width = *options.segment_width;
        out.width_from = WidthSource::option;
    }

    runs::Replay replayed;
    const auto best = replay_behaviour(run_db, options.individual, &replayed);
    out.individual_id = replayed.individual_id;
    out.reward = replayed.stored_reward;
    const auto channels = static_cast<std::size_t>(sim::kChannels);
    if (width > best.size() / channels) {
        throw ConfigError(concat(options.width_name, ' ', width, " exceeds the ", best.size() / channels,
                                 " steps of the behaviours of ", run_db.string()));
    }
    out.calibration = calibrate_behaviours(best, {}, channels, width, {}, options.neighbours);
    out.reading = options.reading;
    if (options.reading == DeltaReading::windows)
        out.windows = kb::calibrate_delta_windows(best, channels, width, options.neighbours);
    if (options.deltas.empty()) return out;

    // the size table: one KB per delta, fed batch by batch in id order
    runs::EvolveConfig config = runs::EvolveConfig::from_json(
        run.config, run_db.string() + " (stored config)", {}, runs::ConfigOrigin::stored);
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
            genomes.push_back(
                nn::Genome::from_json(runs::load_genome(connection, run.id, ids[start + k]).genome));
        behaviours.assign(n * size, 0.0f);
        parallel_for(n, options.threads, [&](std::size_t k) {
            evaluate_genome(*task, genomes[k], config.dnn,
                            std::span<float>(behaviours.data() + k * size, size));
        });
        std::vector<kb::Segments> segments;
        for (std::size_t k = 0; k < n; ++k)
            segments.push_back(kb::segment_behaviour(
                std::span<const float>(behaviours.data() + k * size, size), channels, width));
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
    for (std::size_t d = 0; d < kbs.size(); ++d)
        out.calibration.sizes.push_back({options.deltas[d], kbs[d].size()});
    return out;
}

}  // namespace stepstone::exp
