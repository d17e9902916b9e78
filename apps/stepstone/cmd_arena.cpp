// stepstone arena: check an arena file, print it as JSON, or draw it

#include <iostream>
#include <memory>
#include <string>

#include "commands.hpp"
#include "core/error.hpp"
#include "core/text.hpp"
#include "report/arena_figure.hpp"
#include "report/canvas.hpp"
#include "sim/arena_spec.hpp"
#include "sim/task.hpp"

namespace stepstone::app {

namespace {

struct ArenaFlags {
    std::string file;
    std::string task = "source";
    std::string out;
    bool json = false;
    bool force = false;
};

void run_arena(const ArenaFlags& flags) {
    sim::TaskConfig config;
    config.kind = sim::parse_task_kind(flags.task, "--task");
    if (!flags.file.empty())
        config.arena = std::make_shared<const sim::ArenaSpec>(sim::ArenaSpec::load(flags.file));
    const sim::ArenaSpec& arena = config.arena_spec();
    if (!flags.out.empty()) {
        const auto format = report::format_of(flags.out);
        if (!flags.force && std::filesystem::exists(flags.out)) {
            throw ConfigError(flags.out + " exists (use --force to replace it)");
        }
        const auto task = sim::make_task(config);
        const auto layout = report::ArenaLayout::fit(arena);
        report::Canvas canvas(layout.width, layout.height, format);
        report::draw_arena(canvas, *task, task->door_starts_open(),
                           concat("The ", flags.task, " task in the arena '", arena.name, "'"), layout);
        canvas.save(flags.out, flags.force);
    }
    if (flags.json) {
        std::cout << arena.to_text();
        return;
    }
    std::cout << "arena '" << arena.name << "'" << (flags.file.empty() ? " (the paper's, built in)" : "")
              << ": " << arena.walls.size() << " walls and a door, " << arena.balls.size()
              << " balls (the target task's: ball " << arena.target_ball << "), "
              << arena.basket.lights.size() << " basket lights, reward divisor " << arena.balls.size()
              << " per start\n";
    if (!flags.out.empty()) std::cout << "wrote " << flags.out << '\n';
}

void add_arena_command(CLI::App& app) {
    auto flags = std::make_shared<ArenaFlags>();
    auto* cmd = app.add_subcommand(
        "arena",
        "Check an arena file (walls, door, balls, switch, basket, start poses), print it or draw it");
    cmd->add_option("file", flags->file, "Arena file (JSON, docs/simulator.md); default: the paper's arena");
    cmd->add_option("--task", flags->task, "Task drawn: source (every ball, door closed) or target")
        ->capture_default_str();
    cmd->add_option("--out", flags->out, "Draw the arena: .png or .svg");
    cmd->add_flag("--json", flags->json, "Print the arena as JSON (every key, exact numbers)");
    cmd->add_flag("--force", flags->force, "Replace an existing --out file");
    cmd->footer(example({"stepstone arena examples/arenas/two_rooms.json --out two_rooms.png",
                         "stepstone arena --json > paper.json"}));
    cmd->callback([flags] { run_arena(*flags); });
}

const CommandRegistrar arena_registrar(22, add_arena_command);

}  // namespace

}  // namespace stepstone::app
