// stepstone: one binary, one subcommand per file; this file parses, dispatches
// and maps every escaped exception to one stderr line and an exit code.

#include <algorithm>
#include <exception>
#include <iostream>
#include <utility>
#include <vector>

#include "commands.hpp"
#include "core/error.hpp"
#include "core/text.hpp"

namespace stepstone::app {

namespace {

std::vector<std::pair<int, CommandAdder>>& registry() {
    static std::vector<std::pair<int, CommandAdder>> adders;
    return adders;
}

}  // namespace

CommandRegistrar::CommandRegistrar(int order, CommandAdder adder) { registry().emplace_back(order, adder); }

void add_registered_commands(CLI::App& app) {
    auto adders = registry();
    std::stable_sort(adders.begin(), adders.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    for (const auto& entry : adders) entry.second(app);
}

std::string example(std::initializer_list<const char*> lines) {
    std::string text = "\nExample:";
    for (const char* line : lines) text += std::string("\n  ") + line;
    return text + "\n";
}

}  // namespace stepstone::app

namespace {

// exit codes: 0 ok, 1 runtime/data/database, 2 usage/config, 70 internal
constexpr int kExitRuntime = 1;
constexpr int kExitUsage = 2;
constexpr int kExitInternal = 70;

int fail(const std::string& message, int code) {
    std::cerr << "stepstone: error: " << stepstone::one_line(message) << std::endl;
    return code;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"stepstone: transfer learning for evolutionary robotics by reward shaping"};
    app.set_version_flag("--version", "stepstone " STEPSTONE_VERSION);
    app.require_subcommand(1);
    app.footer(stepstone::app::example({"stepstone db info run.db", "stepstone demo"}));
    stepstone::app::add_registered_commands(app);

    try {
        app.parse(argc, argv);  // runs the chosen command's callback
    } catch (const CLI::ParseError& e) {
        if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
        return fail(e.what(), kExitUsage);
    } catch (const stepstone::ConfigError& e) {
        return fail(e.what(), kExitUsage);
    } catch (const stepstone::Error& e) {
        return fail(e.what(), kExitRuntime);
    } catch (const std::exception& e) {
        return fail(std::string("internal error: ") + e.what(), kExitInternal);
    } catch (...) {
        return fail("internal error: unknown exception", kExitInternal);
    }
    return 0;
}
