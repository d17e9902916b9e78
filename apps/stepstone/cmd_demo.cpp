// stepstone demo: the main job end to end on small settings

#include <iostream>

#include "commands.hpp"
#include "db/database.hpp"

namespace stepstone::app {

namespace {

void run_demo() {
    std::cout << "stepstone " STEPSTONE_VERSION " demo\n"
              << "  database layer: schema version " << db::latest_schema_version() << ", "
              << db::migrations().size() << " migration(s) embedded\n"
              << "  commands: db info, db migrate\n";
}

void add_demo_command(CLI::App& app) {
    auto* demo = app.add_subcommand("demo", "Run the main job end to end on small settings");
    demo->footer(example({"stepstone demo"}));
    demo->callback(run_demo);
}

const CommandRegistrar registrar(1, add_demo_command);

}  // namespace

}  // namespace stepstone::app
