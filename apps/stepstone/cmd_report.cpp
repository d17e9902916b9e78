// stepstone report: an HTML report of a run or a campaign

#include <iostream>
#include <memory>

#include "commands.hpp"
#include "core/error.hpp"
#include "core/text.hpp"
#include "report/report.hpp"

namespace stepstone::app {

namespace {

struct ReportFlags {
    std::string input;
    std::string out;
    int generation = -1;
    double threshold = 0.5;
    bool force = false;
    bool quiet = false;
};

void add_report_command(CLI::App& app) {
    auto flags = std::make_shared<ReportFlags>();
    auto* cmd = app.add_subcommand(
        "report", "Write an HTML report (figures, statistics, KB, configs, provenance) of a run or a campaign");
    cmd->add_option("input", flags->input, "Run file, or campaign directory (holding campaign.db)")->required();
    cmd->add_option("--out", flags->out, "Report directory to create (index.html and its figures)")->required();
    cmd->add_option("--generation", flags->generation,
                    "Campaigns: compare treatments at this generation (default: the target budget)");
    cmd->add_option("--threshold", flags->threshold, "Campaigns: success is best-of-run reward >= this (default 0.5)");
    cmd->add_flag("--force", flags->force, "Replace an existing report directory");
    cmd->add_flag("--quiet", flags->quiet, "No progress on stderr");
    cmd->footer(example({"stepstone report camp --out camp-report", "stepstone report run.db --out run-report --force"}));
    cmd->callback([flags] {
        report::ReportOptions options;
        options.input = flags->input;
        options.out = flags->out;
        options.force = flags->force;
        options.threshold = flags->threshold;
        if (flags->generation != -1) {
            if (flags->generation < 0) throw ConfigError(concat("--generation must be >= 0, got ", flags->generation));
            options.generation = flags->generation;
        }
        if (flags->quiet) options.progress = ProgressMode::quiet;
        const auto summary = report::write_report(options);
        for (const auto& note : summary.notes) std::cerr << "stepstone: note: " << note << '\n';
        std::cout << "wrote " << summary.files.size() << " files; open " << summary.index.string() << '\n';
    });
}

const CommandRegistrar report_registrar(60, add_report_command);

}  // namespace

}  // namespace stepstone::app
