// stepstone bench [CASE...] [--quick] [--csv] [--list] [--target CASE=RATIO]

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "bench/registry.hpp"
#include "bench/runner.hpp"
#include "commands.hpp"
#include "core/error.hpp"
#include "core/progress.hpp"

namespace stepstone::app {

namespace {

struct BenchOptions {
    std::vector<std::string> cases;
    bool quick = false;
    bool csv = false;
    bool list = false;
    std::vector<std::string> targets;  ///< CASE=RATIO, replacing a case's own target
};

// --target CASE=RATIO, each naming a case of this build (a case with a parameter: every row of
// it, or one row CASE/VALUE) and a positive ratio; keyed by row, a later one wins
std::map<std::string, double> parse_targets(const std::vector<std::string>& given,
                                            const bench::Registry& registry) {
    std::map<std::string, double> targets;
    for (const auto& text : given) {
        const auto equals = text.find('=');
        if (equals == std::string::npos)
            throw ConfigError("--target '" + text + "' is not CASE=RATIO (e.g. --target sim=25)");
        const std::string name = text.substr(0, equals);
        const std::vector<const bench::Case*> rows = registry.select(name);
        if (rows.empty()) throw ConfigError("--target names no bench case '" + name + "' (see --list)");
        const std::string number = text.substr(equals + 1);
        std::size_t used = 0;
        double ratio = 0;
        try {
            ratio = std::stod(number, &used);
        } catch (const std::exception&) {
            used = 0;
        }
        if (used == 0 || used != number.size() || !std::isfinite(ratio) || ratio <= 0)
            throw ConfigError("--target " + name + "='" + number + "' is not a positive ratio");
        for (const bench::Case* row : rows) targets[row->name] = ratio;
    }
    return targets;
}

// the rows that fell short of their targets (--target's already in target_ratio), "kb
// 46.2x < 50x" each; a quick run judges only the targets given with --target (its reduced
// workloads are not what the targets are for)
std::vector<std::string> short_of_targets(const std::vector<bench::CaseResult>& results,
                                          const std::map<std::string, double>& targets, bool quick) {
    std::vector<std::string> below;
    for (const auto& r : results) {
        if (!r.skipped.empty() || r.ratio >= r.target_ratio) continue;
        if (quick && !targets.contains(r.name)) continue;
        char line[128];
        std::snprintf(line, sizeof line, "%s %.3gx < %gx", r.name.c_str(), r.ratio, r.target_ratio);
        below.emplace_back(line);
    }
    return below;
}

// 241532 -> "242k", 4.8e6 -> "4.80M": rates span six orders of magnitude
std::string human(double value) {
    const char* suffix = "";
    if (value >= 1e9) {
        value /= 1e9;
        suffix = "G";
    } else if (value >= 1e6) {
        value /= 1e6;
        suffix = "M";
    } else if (value >= 1e3) {
        value /= 1e3;
        suffix = "k";
    }
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, value >= 100 ? "%.0f%s" : value >= 10 ? "%.1f%s" : "%.2f%s", value, suffix);
    return buffer;
}

std::string pad(const std::string& text, std::size_t width, bool right) {
    if (text.size() >= width) return text;
    const std::string fill(width - text.size(), ' ');
    return right ? fill + text : text + fill;
}

void print_list(const bench::Registry& registry) {
    for (const auto& c : registry.cases()) {
        char target[32];
        std::snprintf(target, sizeof target, ">= %gx", c.target_ratio);
        std::cout << pad(c.name, 12, false) << pad(c.unit, 14, false) << pad(target, 10, false) << c.description
                  << '\n';
    }
}

// the ratio column is the paired ratio (the median of the rounds' ratios), the rounds column
// their least and greatest
void print_table(const std::vector<bench::CaseResult>& results) {
    std::cout << pad("case", 12, false) << pad("unit", 14, false) << pad("baseline/s", 12, true)
              << pad("candidate/s", 13, true) << pad("ratio", 9, true) << pad("rounds", 15, true)
              << pad("target", 9, true) << '\n';
    for (const auto& r : results) {
        char ratio[32];
        char rounds[48];
        char target[32];
        std::snprintf(ratio, sizeof ratio, "%.2fx", r.ratio);
        std::snprintf(rounds, sizeof rounds, "%.3g-%.3gx", r.ratio_min, r.ratio_max);
        std::snprintf(target, sizeof target, "%gx", r.target_ratio);
        if (!r.skipped.empty()) {
            std::cout << pad(r.name, 12, false) << pad(r.unit, 14, false) << pad("-", 12, true)
                      << pad("-", 13, true) << pad("-", 9, true) << pad("-", 15, true) << pad(target, 9, true)
                      << "  not run: " << r.skipped << '\n';
            continue;
        }
        std::cout << pad(r.name, 12, false) << pad(r.unit, 14, false)
                  << pad(human(r.baseline_per_s), 12, true) << pad(human(r.candidate_per_s), 13, true)
                  << pad(ratio, 9, true) << pad(rounds, 15, true) << pad(target, 9, true) << '\n';
    }
}

void print_csv(const std::vector<bench::CaseResult>& results) {
    std::cout << "case,baseline_per_s,candidate_per_s,ratio,ratio_min,ratio_max,rounds\n";
    for (const auto& r : results) {
        if (!r.skipped.empty()) {
            std::cout << r.name << ",,,,,,\n";  // not run: empty fields (the reason is on stderr)
            continue;
        }
        char line[256];
        std::snprintf(line, sizeof line, "%s,%.6g,%.6g,%.4g,%.4g,%.4g,%zu\n", r.name.c_str(),
                      r.baseline_per_s, r.candidate_per_s, r.ratio, r.ratio_min, r.ratio_max,
                      r.baseline_rates.size());
        std::cout << line;
    }
}

void run_bench(const BenchOptions& options) {
    const bench::Registry registry = bench::default_registry();
    if (options.list) {
        print_list(registry);
        return;
    }

    // validate every name and target before running anything
    const std::map<std::string, double> targets = parse_targets(options.targets, registry);
    std::vector<const bench::Case*> selected;
    for (const auto& name : options.cases) {
        const std::vector<const bench::Case*> rows = registry.select(name);
        if (rows.empty()) {
            std::string known;
            for (const auto& n : registry.names()) known += (known.empty() ? "" : ", ") + n;
            throw ConfigError("unknown bench case '" + name + "' (this build has: " +
                              (known.empty() ? std::string("none") : known) + ")");
        }
        for (const bench::Case* row : rows) {  // each row once, in the order first named
            if (std::find(selected.begin(), selected.end(), row) == selected.end()) selected.push_back(row);
        }
    }
    if (options.cases.empty()) {
        for (const auto& c : registry.cases()) selected.push_back(&c);
    }

    const bench::RunOptions run_options = options.quick ? bench::quick_options() : bench::full_options();
    const auto rounds = static_cast<std::uint64_t>(run_options.repetitions);
    Progress progress("bench round", rounds * selected.size(),
                      options.quick ? ProgressMode::quiet : ProgressMode::automatic);
    std::vector<bench::CaseResult> results;
    std::uint64_t done = 0;
    for (const bench::Case* c : selected) {
        progress.update(done, c->name);
        // a case that cannot run here is reported with its reason; the others still run
        try {
            results.push_back(
                bench::run_case(*c, run_options, [&](int, int) { progress.update(++done, c->name); }));
        } catch (const std::exception& e) {
            bench::CaseResult skipped;
            skipped.name = c->name;
            skipped.unit = c->unit;
            skipped.target_ratio = c->target_ratio;
            skipped.skipped = e.what();
            if (options.csv) std::cerr << "stepstone: bench " << c->name << " not run: " << e.what() << '\n';
            results.push_back(skipped);
        }
    }
    progress.finish();
    for (auto& r : results) {  // the table shows the target each row is judged by
        if (const auto given = targets.find(r.name); given != targets.end()) r.target_ratio = given->second;
    }

    if (options.csv) {
        print_csv(results);
    } else {
        print_table(results);
    }
    std::cout.flush();
    const std::vector<std::string> below = short_of_targets(results, targets, options.quick);
    if (!below.empty()) {
        std::string list;
        for (const auto& row : below) list += (list.empty() ? "" : ", ") + row;
        throw Error("bench: " + std::to_string(below.size()) +
                    (below.size() == 1 ? " case fell short of its target: "
                                       : " cases fell short of their targets: ") +
                    list);
    }
}

}  // namespace

namespace {

void add_bench_command(CLI::App& app) {
    auto options = std::make_shared<BenchOptions>();
    auto* cmd = app.add_subcommand("bench", "Time each hot path against its baseline in the same process");
    cmd->add_option("case", options->cases,
                    "Cases to run (default: all; see --list); a case with a parameter runs every row of it "
                    "(serve: serve/1, serve/2, serve/8), CASE/VALUE one row");
    cmd->add_flag("--quick", options->quick, "Reduced workloads and fewer rounds: a few seconds in all");
    cmd->add_flag(
        "--csv", options->csv,
        "Print case,baseline_per_s,candidate_per_s,ratio,ratio_min,ratio_max,rounds (ratio: the median of "
        "the rounds' candidate / baseline)");
    cmd->add_flag("--list", options->list, "List the cases of this build with their units and targets");
    cmd->add_option(
           "--target", options->targets,
           "CASE=RATIO: judge CASE (every row of a case with a parameter, or CASE/VALUE one row) "
           "against RATIO instead of its own target (repeatable; also judged by --quick, which otherwise "
           "judges none)")
        ->allow_extra_args(false);
    cmd->footer(example({"stepstone bench", "stepstone bench sim nn --csv", "stepstone bench --quick",
                         "stepstone bench episode --target episode=25", "stepstone bench serve/2",
                         "stepstone bench --list"}) +
                "\nExit status 1, after the whole table, when a case that ran fell short of its target.");
    cmd->callback([options] { run_bench(*options); });
}

const CommandRegistrar bench_registrar(80, add_bench_command);

}  // namespace

}  // namespace stepstone::app
