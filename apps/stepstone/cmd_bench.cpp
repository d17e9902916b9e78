// stepstone bench [CASE...] [--quick] [--csv] [--list]

#include <cstdio>
#include <iostream>
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
};

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

    // validate every name before running anything
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

    if (options.csv) {
        print_csv(results);
    } else {
        print_table(results);
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
    cmd->footer(example({"stepstone bench", "stepstone bench sim nn --csv", "stepstone bench --quick",
                         "stepstone bench --list"}));
    cmd->callback([options] { run_bench(*options); });
}

const CommandRegistrar bench_registrar(80, add_bench_command);

}  // namespace

}  // namespace stepstone::app
