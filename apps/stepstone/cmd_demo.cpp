// stepstone demo: the main job end to end on small settings

#include <filesystem>
#include <iostream>
#include <memory>

#include "commands.hpp"
#include "core/error.hpp"
#include "db/database.hpp"
#include "db/digest.hpp"
#include "db/kb_store.hpp"
#include "exp/evolution.hpp"
#include "exp/replay.hpp"

namespace stepstone::app {

namespace {

struct DemoFlags {
    std::string dir = "demo-out";
    std::string examples = "examples";
    unsigned threads = 0;
    bool quiet = false;
};

void run_demo(const DemoFlags& flags) {
    namespace fs = std::filesystem;
    const fs::path dir = flags.dir;
    const fs::path config = fs::path(flags.examples) / "source_quick.json";
    if (!fs::exists(config)) throw ConfigError(config.string() + ": no such file (set --examples to the examples folder)");
    fs::create_directories(dir);

    // 1. a short source evolution into a run file
    std::cout << "== source evolution (" << config.string() << ") -> " << (dir / "source.db").string() << std::endl;
    exp::EvolveOptions options;
    options.config_path = config;
    options.db_path = dir / "source.db";
    options.threads = flags.threads;
    options.force = true;
    options.progress = flags.quiet ? ProgressMode::quiet : ProgressMode::automatic;
    const auto summary = exp::run_evolve(options);
    std::cout << "   seed " << summary.seed << ", generations 0-" << summary.generations_done << ", "
              << summary.evaluations << " evaluations, best reward " << summary.best_reward << "\n";

    // 2. the best stored policy replays to its stored reward
    const auto replayed = exp::replay(dir / "source.db", "best");
    std::cout << "== replay of the best policy (individual " << replayed.individual_id << "): reward "
              << replayed.result.reward << ", stored " << replayed.stored_reward
              << (replayed.result.reward == replayed.stored_reward ? " (identical)" : " (DIFFERENT)") << "\n";

    // 3. the knowledge base the run built from its policies
    auto connection = db::open_database(dir / "source.db", db::OpenMode::read_only);
    for (const auto& kb : db::list_kbs(connection)) {
        const auto policies = connection.query_int("SELECT sum(policies) FROM kb_source WHERE kb_id = " +
                                                   std::to_string(kb.id));
        std::cout << "== knowledge base \"" << kb.name << "\": " << kb.segments << " segments of "
                  << kb.params.segment_width << " steps x " << kb.params.channels << " channels from "
                  << policies.value_or(0) << " policies (delta " << kb.params.delta << ")\n";
    }

    // 4. the run's digest identifies its results
    std::cout << "== digest " << db::run_digest(connection) << "\n"
              << "   inspect it: stepstone db info " << (dir / "source.db").string() << std::endl;
}

void add_demo_command(CLI::App& app) {
    auto flags = std::make_shared<DemoFlags>();
    auto* demo = app.add_subcommand("demo", "Run the main job end to end on small settings");
    demo->add_option("--dir", flags->dir, "Output folder (default: demo-out)");
    demo->add_option("--examples", flags->examples, "Folder holding the example configs (default: examples)");
    demo->add_option("--threads", flags->threads, "Evaluation threads (default: all cores)");
    demo->add_flag("--quiet", flags->quiet, "No progress on stderr");
    demo->footer(example({"stepstone demo --dir demo-out"}));
    demo->callback([flags] { run_demo(*flags); });
}

const CommandRegistrar registrar(1, add_demo_command);

}  // namespace

}  // namespace stepstone::app
