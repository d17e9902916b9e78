// stepstone shape: r_max and the per-segment KB matches of one stored policy

#include <iostream>
#include <memory>
#include <string>

#include "commands.hpp"
#include "kb_output.hpp"

namespace stepstone::app {

namespace {

struct ShapeFlags {
    std::string kb;
    std::string run;
    std::string individual = "best";
    std::string kb_name;
    bool json = false;
};

void add_shape_command(CLI::App& app) {
    auto flags = std::make_shared<ShapeFlags>();
    auto* cmd = app.add_subcommand(
        "shape", "Look a stored policy's segments up in a knowledge base: r_max and each segment's match");
    cmd->add_option("--kb", flags->kb, "KB file (opened read-only)")->required();
    cmd->add_option("--run", flags->run, "Run database holding the policy (opened read-only)")->required();
    cmd->add_option("--individual", flags->individual, "'best' (default) or an individual id")
        ->check(individual_check());
    cmd->add_option("--kb-name", flags->kb_name, "Which KB of the KB file (default: its only one)");
    cmd->add_flag("--json", flags->json, "Print JSON instead of text");
    cmd->footer(example({"stepstone shape --kb kb.db --run run.db --individual best",
                         "stepstone shape --kb merged.db --run target.db --individual 412 --json"}));
    cmd->callback([flags] {
        const auto shaping = exp::shape_policy(flags->kb, flags->run, flags->individual, flags->kb_name);
        if (flags->json) {
            std::cout << to_json(shaping).dump(2) << '\n';
        } else {
            write_text(std::cout, shaping);
        }
    });
}

const CommandRegistrar shape_registrar(45, add_shape_command);

}  // namespace

}  // namespace stepstone::app
