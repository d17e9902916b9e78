// How the kb commands and `stepstone shape` print their results

#include "kb_output.hpp"

#include <iomanip>
#include <sstream>

#include "core/text.hpp"
#include "db/kb_store.hpp"

namespace stepstone::app {

namespace {

std::string optional_seed_text(const std::optional<std::uint64_t>& seed) {
    return seed ? concat(*seed) : std::string("none");
}

}  // namespace

void write_written(std::ostream& out, const std::string& file, const runs::KbWritten& kb) {
    out << file << ": knowledge base \"" << kb.name << "\", " << kb.segments << " segments (segment_width "
        << kb.params.segment_width << ", channels " << kb.params.channels << ", delta " << kb.params.delta
        << ")";
    if (kb.randomized_seed) out << ", randomized with seed " << *kb.randomized_seed;
    out << '\n';
}

std::string width_source_text(exp::WidthSource source) {
    switch (source) {
        case exp::WidthSource::option:
            return "--segment-width";
        case exp::WidthSource::run_kb:
            return "the run's knowledge base";
        case exp::WidthSource::default_width:
            break;
    }
    return "default";
}

nlohmann::json to_json(const exp::RunCalibration& result) {
    const auto& c = result.calibration;
    nlohmann::json out;
    out["individual_id"] = result.individual_id;
    out["reward"] = result.reward;
    out["segment_width"] = c.segment_width;
    out["segment_width_from"] = width_source_text(result.width_from);
    out["channels"] = c.channels;
    out["neighbours"] = c.neighbours;
    out["segments"] = c.segments;
    out["delta"] = c.delta;
    out["reading"] = exp::to_string(result.reading);
    if (result.windows) {
        out["windows"] = {{"windows", result.windows->windows},
                          {"delta_excluding_overlap", result.windows->excluding_overlap},
                          {"delta_including_overlap", result.windows->including_overlap}};
    }
    out["policies"] = c.policies;
    out["sizes"] = nlohmann::json::array();
    for (const auto& row : c.sizes) out["sizes"].push_back({{"delta", row.delta}, {"segments", row.size}});
    return out;
}

void write_text(std::ostream& out, const exp::RunCalibration& result) {
    const auto& c = result.calibration;
    out << "individual      " << result.individual_id << " (stored reward " << result.reward << ")\n"
        << "segment_width   " << c.segment_width << " (" << width_source_text(result.width_from) << ")\n"
        << "segments        " << c.segments << " of " << c.channels << " channels\n"
        << "delta           " << c.delta << "  (mean distance of each segment to its " << c.neighbours
        << " nearest others, averaged)\n";
    if (result.windows) {
        const auto& w = *result.windows;
        out << "windows         " << w.windows << " of " << c.segment_width << " steps at stride 1\n"
            << "delta (windows) " << w.excluding_overlap << "  (mean distance of each window to its "
            << c.neighbours << " nearest windows that share no step with it, averaged)\n"
            << "                " << w.including_overlap
            << "  (the same with the overlapping windows included)\n";
    }
    if (c.sizes.empty()) return;
    out << "\nKB size over the " << c.policies << " stored policies\n"
        << "  delta       segments\n";
    for (const auto& row : c.sizes) {
        out << "  " << std::left << std::setw(10) << row.delta << std::right << std::setw(10) << row.size
            << '\n';
    }
}

nlohmann::json to_json(const runs::KbStats& stats) {
    nlohmann::json out;
    out["file"] = stats.file;
    out["name"] = stats.name;
    out["segments"] = stats.segments;
    out["segment_width"] = stats.params.segment_width;
    out["channels"] = stats.params.channels;
    out["delta"] = stats.params.delta;
    out["match"] = db::to_string(stats.params.match);
    out["counting"] = kb::to_string(stats.params.counting);
    out["digest"] = stats.digest;
    out["zero_average_segments"] = stats.zero_average;
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

void write_text(std::ostream& out, const runs::KbStats& stats) {
    out << "knowledge base  \"" << stats.name << "\" in " << stats.file << '\n'
        << "segments        " << stats.segments << '\n'
        << "segment_width   " << stats.params.segment_width << '\n'
        << "channels        " << stats.params.channels << '\n'
        << "delta           " << stats.params.delta << '\n'
        << "match           " << db::to_string(stats.params.match) << '\n'
        << "counting        " << kb::to_string(stats.params.counting) << '\n'
        << "randomized_seed " << optional_seed_text(stats.randomized_seed) << '\n'
        << "max average     " << stats.max_average << '\n'
        << "zero average    " << stats.zero_average << " segments ("
        << (stats.segments == 0
                ? 0.0
                : 100.0 * static_cast<double>(stats.zero_average) / static_cast<double>(stats.segments))
        << " %)\n"
        << "content digest  " << stats.digest << '\n';

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

nlohmann::json to_json(const exp::Shaping& shaping) {
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

void write_text(std::ostream& out, const exp::Shaping& shaping) {
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

void write_text(std::ostream& out, const std::string& run_file, const exp::Annotation& done) {
    out << run_file << ": " << done.individuals.size() << " policies, " << done.rows
        << " policy_segment rows, kb_id " << done.kb_id << " (\"" << done.kb_name << "\", "
        << (done.copied ? "copied into the run file" : "already in the run file") << ")\n";
}

}  // namespace stepstone::app
