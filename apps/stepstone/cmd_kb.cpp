// stepstone kb export | merge | randomize | calibrate | stats | annotate

#include <filesystem>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "commands.hpp"
#include "core/error.hpp"
#include "core/text.hpp"
#include "kb_output.hpp"
#include "runs/kb_duplicates.hpp"
#include "runs/run_store.hpp"

namespace stepstone::app {

namespace {

void print_written(const std::string& out, const runs::KbWritten& kb) {
    write_written(std::cout, out, kb);
    // what evolve says when such a KB shapes a run, said when it is made
    if (!(kb.max_average > 0.0)) {
        std::cerr
            << "stepstone: warning: " << out
            << ": the knowledge base's largest average reward is 0, so shaping with it (sum, mo) selects as "
               "none would\n";
    }
}

// ------------------------------------------------------------------- export

struct ExportFlags {
    std::string run;
    std::string out;
    std::string input_name = runs::kRunKbName;
    std::string name;
    std::optional<double> delta;
    bool force = false;
};

void add_export(CLI::App& kb_cmd) {
    auto flags = std::make_shared<ExportFlags>();
    auto* cmd = kb_cmd.add_subcommand("export", "Write a run's knowledge base as a standalone KB file");
    cmd->add_option("run", flags->run, "Run database (opened read-only)")->required();
    cmd->add_option("--out", flags->out, "New KB file (written atomically)")->required();
    cmd->add_option("--kb-name", flags->input_name,
                    "Which KB of the run file (default: " + flags->input_name + ")");
    cmd->add_option("--name", flags->name, "Name of the KB written (default: the input's name)");
    cmd->add_option("--delta", flags->delta,
                    "Coarsen: re-observe the KB's segments under this larger delta (a smaller KB)");
    cmd->add_flag("--force", flags->force, "Overwrite an existing --out file");
    cmd->footer(example({"stepstone kb export run.db --out kb.db",
                         "stepstone kb export run.db --out kb-coarse.db --delta 4"}));
    cmd->callback([flags] {
        print_written(flags->out, runs::export_kb(flags->run, flags->input_name, flags->out, flags->force,
                                                  flags->delta, flags->name));
    });
}

// -------------------------------------------------------------------- merge

struct MergeFlags {
    std::vector<std::string> inputs;
    std::string out;
    std::string name;
    std::string input_name;
    bool force = false;
    bool allow_duplicates = false;
};

void add_merge(CLI::App& kb_cmd) {
    auto flags = std::make_shared<MergeFlags>();
    auto* cmd = kb_cmd.add_subcommand(
        "merge", "Merge KB files: the segments of each later KB are observed into the first under its delta");
    cmd->add_option("kbs", flags->inputs,
                    "Two or more KB or run files (opened read-only), merged in this order")
        ->required();
    cmd->add_option("--out", flags->out, "New KB file (written atomically)")->required();
    cmd->add_option("--name", flags->name, "Name of the merged KB (default: the first KB's name)");
    cmd->add_option("--kb-name", flags->input_name,
                    "Which KB to read from each input (default: its only one)");
    cmd->add_flag("--force", flags->force, "Overwrite an existing --out file");
    cmd->add_flag("--allow-duplicates", flags->allow_duplicates,
                  "Merge even the same file twice, or KBs sharing a source run (counts add twice)");
    cmd->footer(example({"stepstone kb merge a.db b.db c.db --out merged.db"}));
    cmd->callback([flags] {
        std::vector<std::filesystem::path> inputs(flags->inputs.begin(), flags->inputs.end());
        try {
            print_written(flags->out, runs::merge_kb_files(inputs, flags->out, flags->name, flags->force,
                                                           flags->input_name, flags->allow_duplicates));
        } catch (const runs::DuplicateKbs& e) {
            throw ConfigError(concat(e.what(), " (use --allow-duplicates to merge anyway)"));
        }
    });
}

// ---------------------------------------------------------------- randomize

struct RandomizeFlags {
    std::string in;
    std::string out;
    std::uint64_t seed = 0;
    std::string name;
    std::string input_name;
    bool force = false;
};

void add_randomize(CLI::App& kb_cmd) {
    auto flags = std::make_shared<RandomizeFlags>();
    auto* cmd = kb_cmd.add_subcommand(
        "randomize", "The control KB: same segments, average rewards drawn from U[0, 1) with a seed");
    cmd->add_option("kb", flags->in, "KB file (opened read-only)")->required();
    cmd->add_option("--out", flags->out, "New KB file (written atomically)")->required();
    cmd->add_option("--seed", flags->seed, "Seed of the draws (stored as randomized_seed)")->required();
    cmd->add_option("--name", flags->name, "Name of the output KB (default: the input's name + \"-rand\")");
    cmd->add_option("--kb-name", flags->input_name, "Which KB of the input (default: its only one)");
    cmd->add_flag("--force", flags->force, "Overwrite an existing --out file");
    cmd->footer(example({"stepstone kb randomize merged.db --out rand.db --seed 7"}));
    cmd->callback([flags] {
        print_written(flags->out, runs::randomize_kb_file(flags->in, flags->out, flags->seed, flags->name,
                                                          flags->force, flags->input_name));
    });
}

// ---------------------------------------------------------------- calibrate

struct CalibrateFlags {
    std::string run;
    std::string individual = "best";
    std::string deltas = "0.5,1,1.5,1.83,2,2.5,3,4";
    std::string reading = "segments";
    std::optional<std::size_t> segment_width;
    std::size_t neighbours = kb::kDefaultNeighbours;
    unsigned threads = 0;
    bool json = false;
    bool quiet = false;
};

void run_calibrate(const CalibrateFlags& flags) {
    exp::CalibrateOptions options;
    options.individual = flags.individual;
    options.reading = flags.reading == "windows" ? exp::DeltaReading::windows : exp::DeltaReading::segments;
    options.segment_width = flags.segment_width;
    options.width_name = "--segment-width";
    if (flags.deltas != "none") options.deltas = exp::parse_deltas(flags.deltas, "--deltas");
    options.neighbours = flags.neighbours;
    options.threads = flags.threads;
    options.progress = flags.quiet ? ProgressMode::quiet : ProgressMode::automatic;
    if (options.neighbours == 0) throw ConfigError("--neighbours must be >= 1, got 0");
    const auto result = exp::calibrate_run(flags.run, options);
    if (flags.json) {
        std::cout << to_json(result).dump(2) << '\n';
    } else {
        write_text(std::cout, result);
    }
}

void add_calibrate(CLI::App& kb_cmd) {
    auto flags = std::make_shared<CalibrateFlags>();
    auto* cmd = kb_cmd.add_subcommand(
        "calibrate",
        "The paper's delta rule on a stored policy, and the KB size per delta over the run's policies");
    cmd->add_option("run", flags->run, "Run database (opened read-only)")->required();
    cmd->add_option("--individual", flags->individual, "The successful policy: 'best' (default) or an id")
        ->check(individual_check());
    cmd->add_option("--deltas", flags->deltas,
                    "Comma-separated deltas for the size table (default: " + flags->deltas +
                        "), or 'none' for the delta alone");
    cmd->add_option("--reading", flags->reading,
                    "How the rule reads 'the 20 closest behaviors': segments (the policy's non-overlapping "
                    "segments, default) or windows (every window of the segment width at stride 1, given "
                    "with and without the windows that overlap it; the segments reading is printed too)")
        ->check(CLI::IsMember({"segments", "windows"}));
    cmd->add_option("--segment-width", flags->segment_width,
                    "Steps per segment (default: the run's knowledge base's, else " +
                        std::to_string(kb::kDefaultSegmentWidth) + ")");
    cmd->add_option(
        "--neighbours", flags->neighbours,
        "Nearest segments averaged by the rule (default: " + std::to_string(flags->neighbours) + ")");
    cmd->add_option(
           "--threads", flags->threads,
           "Replays and size-table KBs at once, 1 to 1024 (default: all cores); results do not depend on it")
        ->check(CLI::Range(1u, 1024u));
    cmd->add_flag("--json", flags->json, "Print JSON instead of text");
    cmd->add_flag("--quiet", flags->quiet, "No progress on stderr");
    cmd->footer(example({"stepstone kb calibrate run.db --individual best",
                         "stepstone kb calibrate run.db --reading windows --deltas none",
                         "stepstone kb calibrate run.db --deltas 0.5,1,1.83,2.5 --segment-width 20 --json"}));
    cmd->callback([flags] { run_calibrate(*flags); });
}

// -------------------------------------------------------------------- stats

struct StatsFlags {
    std::string kb;
    std::string input_name;
    bool json = false;
};

void add_stats(CLI::App& kb_cmd) {
    auto flags = std::make_shared<StatsFlags>();
    auto* cmd = kb_cmd.add_subcommand(
        "stats", "Size, parameters, average-reward histogram, counts and provenance of a knowledge base");
    cmd->add_option("kb", flags->kb, "KB or run file (opened read-only)")->required();
    cmd->add_option("--kb-name", flags->input_name, "Which KB of the file (default: its only one)");
    cmd->add_flag("--json", flags->json, "Print JSON instead of text");
    cmd->footer(example({"stepstone kb stats kb.db", "stepstone kb stats run.db --kb-name run --json"}));
    cmd->callback([flags] {
        const auto stats = runs::kb_file_stats(flags->kb, flags->input_name);
        if (flags->json) {
            std::cout << to_json(stats).dump(2) << '\n';
        } else {
            write_text(std::cout, stats);
        }
    });
}

// ----------------------------------------------------------------- annotate

struct AnnotateFlags {
    std::string run;
    std::string kb;
    std::string individuals = "best";
    std::string kb_name;
    std::string as_name;
};

void add_annotate(CLI::App& kb_cmd) {
    auto flags = std::make_shared<AnnotateFlags>();
    auto* cmd = kb_cmd.add_subcommand(
        "annotate",
        "Replay stored policies and record each segment's KB match in the run file (policy_segment)");
    cmd->add_option("run", flags->run, "Run database (updated in one transaction)")->required();
    cmd->add_option("--kb", flags->kb, "KB file (opened read-only); copied into the run file")->required();
    cmd->add_option("--individuals", flags->individuals,
                    "best (default), front (the last population's first front) or all stored genomes");
    cmd->add_option("--kb-name", flags->kb_name, "Which KB of the KB file (default: its only one)");
    cmd->add_option("--as", flags->as_name, "Name of the KB's copy in the run file (default: its own name)");
    cmd->footer(example({"stepstone kb annotate run.db --kb kb.db --individuals front",
                         "sqlite3 run.db < queries/policy_saliency.sql"}));
    cmd->callback([flags] {
        const auto which = exp::parse_policy_set(flags->individuals, "--individuals");
        try {
            write_text(std::cout, flags->run,
                       exp::annotate_run(flags->run, flags->kb, which, flags->kb_name, flags->as_name));
        } catch (const exp::KbNameTaken& e) {
            throw DataError(concat(e.what(), "; choose another name with --as"));
        }
    });
}

void add_kb_command(CLI::App& app) {
    auto* kb_cmd =
        app.add_subcommand("kb", "Export, merge, randomize, calibrate, inspect and apply knowledge bases");
    kb_cmd->require_subcommand(1);
    kb_cmd->footer(example({"stepstone kb export run.db --out kb.db",
                            "stepstone kb merge a.db b.db --out merged.db", "stepstone kb stats merged.db"}));
    add_export(*kb_cmd);
    add_merge(*kb_cmd);
    add_randomize(*kb_cmd);
    add_calibrate(*kb_cmd);
    add_stats(*kb_cmd);
    add_annotate(*kb_cmd);
}

const CommandRegistrar kb_registrar(40, add_kb_command);

}  // namespace

}  // namespace stepstone::app
