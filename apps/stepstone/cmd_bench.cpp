// stepstone bench [CASE...] [--quick] [--csv] [--list]

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

// --target CASE=RATIO, each naming a case of this build and a positive ratio
std::map<std::string, double> parse_targets(const std::vector<std::string>& given,
                                            const bench::Registry& registry) {
    std::map<std::string, double> targets;
    for (const auto& text : given) {
        const auto equals = text.find('=');
        if (equals == std::string::npos)
            throw ConfigError("--target '" + text + "' is not CASE=RATIO (e.g. --target sim=25)");
        const std::string name = text.substr(0, equals);
        if (registry.find(name) == nullptr)
            throw ConfigError("--target names no bench case '" + name + "' (see --list)");
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
        targets[name] = ratio;
    }
    return targets;
}

// the rows that fell short of their targets (--target's already in target_ratio), "kb-loop
// 156x < 500x" each; a quick run judges only the targets given with --target (its reduced
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

void print_table(const std::vector<bench::CaseResult>& results) {
    std::cout << pad("case", 12, false) << pad("unit", 14, false) << pad("baseline/s", 12, true)
              << pad("candidate/s", 13, true) << pad("ratio", 9, true) << pad("target", 9, true) << '\n';
    for (const auto& r : results) {
        char ratio[32];
        char target[32];
        std::snprintf(ratio, sizeof ratio, "%.2fx", r.ratio);
        std::snprintf(target, sizeof target, "%gx", r.target_ratio);
        if (!r.skipped.empty()) {
            std::cout << pad(r.name, 12, false) << pad(r.unit, 14, false) << pad("-", 12, true)
                      << pad("-", 13, true) << pad("-", 9, true) << pad(target, 9, true)
                      << "  not run: " << r.skipped << '\n';
            continue;
        }
        std::cout << pad(r.name, 12, false) << pad(r.unit, 14, false) << pad(human(r.baseline_per_s), 12, true)
                  << pad(human(r.candidate_per_s), 13, true) << pad(ratio, 9, true) << pad(target, 9, true) << '\n';
    }
}

void print_csv(const std::vector<bench::CaseResult>& results) {
    std::cout << "case,baseline_per_s,candidate_per_s,ratio\n";
    for (const auto& r : results) {
        if (!r.skipped.empty()) {
            std::cout << r.name << ",,,\n";  // not run: empty fields (the reason is on stderr)
            continue;
        }
        char line[256];
        std::snprintf(line, sizeof line, "%s,%.6g,%.6g,%.4g\n", r.name.c_str(), r.baseline_per_s, r.candidate_per_s,
                      r.ratio);
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
        const bench::Case* c = registry.find(name);
        if (c == nullptr) {
            std::string known;
            for (const auto& n : registry.names()) known += (known.empty() ? "" : ", ") + n;
            throw ConfigError("unknown bench case '" + name + "' (this build has: " +
                              (known.empty() ? std::string("none") : known) + ")");
        }
        selected.push_back(c);
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
    cmd->add_option("case", options->cases, "Cases to run (default: all; see --list)");
    cmd->add_flag("--quick", options->quick, "Reduced workloads and fewer rounds: a few seconds in all");
    cmd->add_flag("--csv", options->csv, "Print case,baseline_per_s,candidate_per_s,ratio");
    cmd->add_flag("--list", options->list, "List the cases of this build with their units and targets");
    cmd->add_option("--target", options->targets,
                    "CASE=RATIO: judge CASE against RATIO instead of its own target (repeatable; "
                    "also judged by --quick, which otherwise judges none)")
        ->allow_extra_args(false);
    cmd->footer(example({"stepstone bench", "stepstone bench sim nn --csv", "stepstone bench --quick",
                         "stepstone bench episode --target episode=25", "stepstone bench --list"}) +
                "\nExit status 1, after the whole table, when a case that ran fell short of its target.");
    cmd->callback([options] { run_bench(*options); });
}

const CommandRegistrar bench_registrar(80, add_bench_command);

}  // namespace

}  // namespace stepstone::app
