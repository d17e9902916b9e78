#include "runs/pooled_stats.hpp"

#include <algorithm>
#include <charconv>
#include <fstream>
#include <map>
#include <utility>

#include "core/error.hpp"
#include "core/text.hpp"
#include "runs/csv_reader.hpp"
#include "stats/summary.hpp"

namespace stepstone::runs {

namespace fs = std::filesystem;

namespace {

using RunKey = std::pair<Treatment, std::uint64_t>;

constexpr std::string_view kRunsHeader =
    "treatment,seed,generation,best_reward,success,policies,ball_policies,mean_r_max";
constexpr std::string_view kEventsHeader = "treatment,seed,event,generation,observed";

// One CSV line split at its commas, with the place it came from for errors.
struct Line {
    std::string where;  // "file line n"
    std::vector<std::string> fields;
};

std::vector<Line> read_csv(const fs::path& file, std::string_view header) {
    const auto records = read_csv_records(file);
    const auto names = records.empty() ? std::vector<std::string>{} : records.front().fields;
    const std::string expected(header);
    std::string first;
    for (std::size_t i = 0; i < names.size(); ++i) first += (i ? "," : "") + names[i];
    if (first != expected) {
        if (!names.empty() && names.front().empty() && first.substr(1) == expected) {
            throw DataError(concat(file.string(),
                                   ": its first column has no name (row names, as R's write.csv adds them: "
                                   "write it with row.names = FALSE)"));
        }
        throw DataError(
            concat(file.string(), ": not the expected CSV (its first line should be '", header, "')"));
    }
    const std::size_t columns = names.size();
    std::vector<Line> lines;
    for (std::size_t r = 1; r < records.size(); ++r) {
        Line line{concat(file.string(), " line ", records[r].line), records[r].fields};
        if (line.fields.size() != columns) {
            throw DataError(concat(line.where, ": ", line.fields.size(), " fields, expected ", columns));
        }
        lines.push_back(std::move(line));
    }
    return lines;
}

template <typename T>
T parse_number(const Line& line, std::size_t field, std::string_view name) {
    const std::string& text = line.fields[field];
    T value{};
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (error != std::errc() || end != text.data() + text.size() || text.empty()) {
        throw DataError(concat(line.where, ": ", name, " '", text, "' is not a number"));
    }
    return value;
}

Treatment parse_run_treatment(const Line& line) {
    try {
        return parse_treatment(line.fields[0], concat(line.where, ": treatment"));
    } catch (const ConfigError& e) {
        throw DataError(e.what());
    }
}

RunRow parse_run(const Line& line) {
    RunRow row;
    row.treatment = parse_run_treatment(line);
    row.seed = parse_number<std::uint64_t>(line, 1, "seed");
    row.generation = parse_number<int>(line, 2, "generation");
    row.best_reward = parse_number<double>(line, 3, "best_reward");
    row.policies = parse_number<std::int64_t>(line, 5, "policies");
    row.ball_policies = parse_number<std::int64_t>(line, 6, "ball_policies");
    // empty where no KB shaped the run; R writes NA for it
    if (!line.fields[7].empty() && line.fields[7] != "NA")
        row.mean_r_max = parse_number<double>(line, 7, "mean_r_max");
    if (row.generation < 0 || !(row.best_reward >= 0.0 && row.best_reward <= 1.0) || row.policies < 0 ||
        row.ball_policies < 0 || row.ball_policies > row.policies) {
        throw DataError(concat(line.where,
                               ": out of range (a generation, best_reward within [0, 1] and "
                               "0 <= ball_policies <= policies are expected)"));
    }
    return row;
}

bool same_run(const RunRow& a, const RunRow& b) {
    return a.generation == b.generation && a.best_reward == b.best_reward && a.policies == b.policies &&
           a.ball_policies == b.ball_policies && a.mean_r_max == b.mean_r_max;
}

std::string run_name(const RunKey& key) { return concat(to_string(key.first), " seed ", key.second); }

// One run's events as read, with the generation its censored milestones give.
struct ReadEvents {
    FirstEvents first;
    std::array<bool, kMilestones> seen{};
    std::optional<int> censored_at;
    std::string file;
};

}  // namespace

PooledStats pool_stats(std::span<const fs::path> runs_files, std::span<const fs::path> events_files,
                       double threshold) {
    if (runs_files.empty() || events_files.empty()) {
        throw ConfigError(concat("give at least one runs CSV (", option_name("runs_files"),
                                 ") and one events CSV (", option_name("events_files"), ")"));
    }
    if (!(threshold >= 0.0 && threshold <= 1.0)) {
        throw ConfigError(concat(option_name("threshold"), " must be within [0, 1], got ", threshold));
    }
    PooledStats stats;
    stats.threshold = threshold;
    std::vector<Treatment> order;
    std::map<RunKey, std::pair<RunRow, std::string>> runs;
    std::map<RunKey, std::size_t> repeated;  // index into stats.repeated
    for (const auto& file : runs_files) {
        stats.runs_files.push_back(file.string());
        for (const auto& line : read_csv(file, kRunsHeader)) {
            const RunRow row = parse_run(line);
            const RunKey key{row.treatment, row.seed};
            if (std::find(order.begin(), order.end(), row.treatment) == order.end())
                order.push_back(row.treatment);
            const auto [it, fresh] = runs.emplace(key, std::pair{row, file.string()});
            if (fresh) continue;
            if (!same_run(it->second.first, row)) {
                throw DataError(concat(it->second.second, " and ", line.where, " disagree on run ",
                                       run_name(key), " (best_reward ", it->second.first.best_reward,
                                       " against ", row.best_reward,
                                       "); the same seed and treatment should give the same run"));
            }
            auto [at, first_repeat] = repeated.emplace(key, stats.repeated.size());
            if (first_repeat) stats.repeated.push_back({key.first, key.second, {it->second.second}});
            stats.repeated[at->second].files.push_back(file.string());
        }
    }
    if (runs.empty()) throw DataError("the runs CSVs hold no run");
    std::map<RunKey, ReadEvents> events;
    for (const auto& file : events_files) {
        stats.events_files.push_back(file.string());
        std::map<RunKey, ReadEvents> here;  // this file's runs, compared with the others' once complete
        for (const auto& line : read_csv(file, kEventsHeader)) {
            const RunKey key{parse_run_treatment(line), parse_number<std::uint64_t>(line, 1, "seed")};
            Milestone m;
            try {
                m = parse_milestone(line.fields[2], concat(line.where, ": event"));
            } catch (const ConfigError& e) {
                throw DataError(e.what());
            }
            const int generation = parse_number<int>(line, 3, "generation");
            const std::string& observed = line.fields[4];
            if (generation < 0 || (observed != "0" && observed != "1")) {
                throw DataError(concat(line.where, ": a generation >= 0 and observed 0 or 1 are expected"));
            }
            ReadEvents& read = here[key];
            read.file = file.string();
            const auto k = static_cast<std::size_t>(m);
            if (read.seen[k])
                throw DataError(
                    concat(line.where, ": a second ", line.fields[2], " row of run ", run_name(key)));
            read.seen[k] = true;
            if (observed == "1") {
                read.first[k] = generation;
            } else if (read.censored_at && *read.censored_at != generation) {
                throw DataError(concat(line.where, ": run ", run_name(key), " is censored at generations ",
                                       *read.censored_at, " and ", generation));
            } else {
                read.censored_at = generation;
            }
        }
        for (auto& [key, read] : here) {
            if (std::count(read.seen.begin(), read.seen.end(), true) != static_cast<long>(kMilestones)) {
                throw DataError(concat(file.string(), ": run ", run_name(key),
                                       " lacks some of its four milestones (press, pickup, release, ball)"));
            }
            const auto [it, fresh] = events.emplace(key, read);
            if (!fresh && it->second.first != read.first) {
                throw DataError(concat(it->second.file, " and ", file.string(),
                                       " disagree on the events of run ", run_name(key),
                                       "; the same seed and treatment should give the same run"));
            }
        }
    }

    stats.generation = runs.begin()->second.first.generation;
    for (const auto& [key, entry] : runs) {
        const auto& [row, file] = entry;
        if (row.generation != stats.generation) {
            throw DataError(concat("runs compared at different generations (", stats.generation, " in ",
                                   runs.begin()->second.second, ", ", row.generation, " for ", run_name(key),
                                   " in ", file, "); pool runs exported at one generation (the statistics' ",
                                   option_name("generation"), ")"));
        }
        const auto found = events.find(key);
        if (found == events.end())
            throw DataError(concat("run ", run_name(key), " of ", file, " has no events in the events CSVs"));
        const ReadEvents& read = found->second;
        const bool late = std::any_of(read.first.begin(), read.first.end(),
                                      [&](const std::optional<int>& g) { return g && *g > row.generation; });
        if (late || (read.censored_at && *read.censored_at != row.generation)) {
            throw DataError(concat(read.file, ": the events of run ", run_name(key),
                                   " do not end at generation ", row.generation, " as its row in ", file,
                                   " does"));
        }
    }
    for (const auto& [key, read] : events) {
        if (!runs.contains(key))
            throw DataError(concat(read.file, ": run ", run_name(key), " is in no runs CSV"));
    }

    // campaign order: seed-major, treatments in their order of first appearance
    const auto rank = [&](Treatment t) { return std::find(order.begin(), order.end(), t) - order.begin(); };
    std::vector<RunKey> keys;
    for (const auto& entry : runs) keys.push_back(entry.first);
    std::sort(keys.begin(), keys.end(), [&](const RunKey& a, const RunKey& b) {
        return a.second != b.second ? a.second < b.second : rank(a.first) < rank(b.first);
    });
    for (const auto& key : keys) {
        RunRow row = runs.at(key).first;
        row.success = row.best_reward >= threshold;
        stats.runs.push_back(row);
        stats.run_events.push_back({key.first, key.second, events.at(key).first});
    }
    for (Treatment t : order) stats.treatments.push_back(treatment_result(t, stats.runs, threshold));
    stats.tests = pair_tests(stats.treatments);
    stats.events = campaign_events(stats.run_events, order, stats.generation);
    return stats;
}

void write_pooled_text(std::ostream& out, const PooledStats& stats, Milestone event) {
    out << "pooled: " << stats.runs.size() << " runs at generation " << stats.generation
        << "; success = best-of-run reward >= " << stats.threshold << "\n";
    for (std::size_t k = 0; k < stats.runs_files.size(); ++k)
        out << "  runs   " << stats.runs_files[k] << "\n";
    for (std::size_t k = 0; k < stats.events_files.size(); ++k)
        out << "  events " << stats.events_files[k] << "\n";
    if (!stats.repeated.empty()) {
        out << stats.repeated.size() << " runs found in more than one input, identical in each:";
        for (const auto& r : stats.repeated) out << " " << to_string(r.treatment) << "/" << r.seed;
        out << "\n";
    }
    out << "\n";
    write_treatment_tables(out, stats.treatments, "mean over runs of each input's mean_r_max",
                           stats.generation);
    write_pair_tests(out, stats.tests, stats.generation);
    write_events_text(out, stats.events, event);
}

}  // namespace stepstone::runs
