// stepstone demo: the main job end to end on small settings

#include <filesystem>
#include <iostream>
#include <memory>

#include "commands.hpp"
#include "core/error.hpp"
#include "db/database.hpp"
#include "db/kb_store.hpp"
#include "evolve_flags.hpp"
#include "exp/campaign/campaign.hpp"
#include "report/report.hpp"
#include "runs/campaign_stats.hpp"
#include "runs/replay.hpp"

namespace stepstone::app {

namespace {

struct DemoFlags {
    std::string dir = "demo-out";
    std::string examples = "examples";
    unsigned jobs = 0;
    bool quiet = false;
};

void run_demo(const DemoFlags& flags) {
    namespace fs = std::filesystem;
    const fs::path dir = flags.dir;
    const fs::path config = fs::path(flags.examples) / "campaign_quick.json";
    if (!fs::exists(config)) throw ConfigError(config.string() + ": no such file (set --examples to the examples folder)");
    if (fs::exists(dir) && !fs::is_directory(dir)) {
        throw ConfigError(dir.string() + ": exists and is not a directory (--dir names the demo's output folder)");
    }
    fs::create_directories(dir);
    const fs::path camp = dir / "campaign";

    // 1. the paper's protocol in small: source run, its KB, five treatments and a seeded one (target)
    const bool resume = fs::exists(camp / "campaign.db");
    std::cout << "== campaign (" << config.string() << ") -> " << camp.string()
              << (resume ? " (resumed: finished runs are kept)" : "") << std::endl;
    exp::CampaignOptions options;
    options.config_path = config;
    options.run_command = evolve_run_command();
    options.dir = camp;
    options.jobs = flags.jobs;
    options.resume = resume;
    options.progress = flags.quiet ? ProgressMode::quiet : ProgressMode::automatic;
    const auto summary = exp::run_campaign(options);
    std::cout << "   " << summary.finished << "/" << summary.runs << " runs finished" << std::endl;
    exp::throw_on_failures(summary, camp, std::cerr);

    // 2. the best source policy replays to its stored reward
    const fs::path source = camp / "source" / "seed-1.db";
    const auto replayed = runs::replay(source, "best");
    std::cout << "== replay of the best source policy (individual " << replayed.individual_id << "): reward "
              << replayed.result.reward << ", stored " << replayed.stored_reward
              << (replayed.result.reward == replayed.stored_reward ? " (identical)" : " (DIFFERENT)") << "\n";

    // 3. the knowledge base exported from the source run, and its randomized twin
    for (const char* file : {"kb/kb.db", "kb/kb-rand.db"}) {
        auto connection = db::open_database(camp / file, db::OpenMode::read_only);
        for (const auto& kb : db::list_kbs(connection)) {
            const auto stored = db::load_kb(connection, kb.name);
            std::cout << "== " << file << ": " << kb.segments << " segments of " << kb.params.segment_width
                      << " steps x " << kb.params.channels << " channels, largest average reward "
                      << stored.kb.max_average() << (kb.randomized_seed ? " (randomized)" : "") << "\n";
        }
    }

    // 4. the statistics of the target runs (the paper's Fig. 6, Fig. 7 and appendix), with the time
    // to the first ball: the milestone the seeded arm reaches within the demo's generations
    std::cout << "== statistics (stepstone stats " << camp.string() << " --event ball)\n";
    runs::write_text(std::cout, runs::campaign_stats(camp, std::nullopt, 0.5), runs::Milestone::ball);
    std::cout << "   a demo is one small sample (3 seeds, 30 generations): it shows the machinery, and its\n"
                 "   seed arm (started from a paper-size source run's 100 best policies,\n"
                 "   examples/fixtures/demo_seeds.db.gz) shows transfer by reuse. What the\n"
                 "   pre-registered experiments found, on 20 to 40 runs an arm, is in docs/results.md\n"
                 "   (sections 9 to 12).\n";
    std::cout << "   query the runs with SQL: sqlite3 " << (camp / "campaign.db").string()
              << " 'SELECT file, best_reward FROM campaign_run'" << std::endl;

    // 5. the report: every figure of the paper for this campaign, in one page
    report::ReportOptions report_options;
    report_options.input = camp;
    report_options.out = dir / "report";
    report_options.force = true;  // a rerun of the demo refreshes its report
    report_options.progress = options.progress;
    const auto report = report::write_report(report_options);
    std::cout << "== report: " << report.files.size() << " files\n"
              << "   open " << fs::absolute(report.index).lexically_normal().string() << std::endl;
}

void add_demo_command(CLI::App& app) {
    auto flags = std::make_shared<DemoFlags>();
    auto* demo = app.add_subcommand("demo", "Run the main job end to end on small settings: a quick campaign, its statistics and its HTML report");
    demo->add_option("--dir", flags->dir, "Output folder (default: demo-out)");
    demo->add_option("--examples", flags->examples, "Folder holding the example configs (default: examples)");
    demo->add_option("--jobs", flags->jobs, "Runs at a time (default: every core)");
    demo->add_flag("--quiet", flags->quiet, "No progress on stderr");
    demo->footer(example({"stepstone demo --dir demo-out"}));
    demo->callback([flags] { run_demo(*flags); });
}

const CommandRegistrar demo_registrar(1, add_demo_command);

}  // namespace

}  // namespace stepstone::app
