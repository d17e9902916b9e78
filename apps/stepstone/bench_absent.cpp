// `stepstone bench` in a build configured with STEPSTONE_BENCH=OFF (the sanitize
// preset): the command exists, so that asking for it says why it cannot run.

#include "commands.hpp"
#include "core/error.hpp"

namespace stepstone::app {

namespace {

void add_bench_absent_command(CLI::App& app) {
    auto* cmd = app.add_subcommand("bench", "Not in this build (configured with STEPSTONE_BENCH=OFF)");
    cmd->allow_extras();
    cmd->footer(example({"cmake --preset release && cmake --build --preset release",
                         "build/release/apps/stepstone/stepstone bench --quick"}));
    cmd->callback([] {
        throw ConfigError(
            "this build has no bench command (configured with STEPSTONE_BENCH=OFF, "
            "as the sanitize preset is); time with a Release build: cmake --preset release");
    });
}

const CommandRegistrar bench_absent_registrar(80, add_bench_absent_command);

}  // namespace

}  // namespace stepstone::app
