// stepstone render: a stored policy's trajectory, coloured by the saliency of its segments

#include <algorithm>
#include <charconv>
#include <iostream>
#include <memory>

#include "commands.hpp"
#include "core/error.hpp"
#include "core/text.hpp"
#include "report/arena_figure.hpp"
#include "report/chart.hpp"

namespace stepstone::app {

namespace {

struct RenderFlags {
    std::string db;
    std::string individual = "best";
    std::string kb;
    std::string kb_name;
    int start = 1;
    std::string steps;
    int heading_every = 50;
    std::string out;
    std::string saliency_out;
    bool force = false;
};

int parse_int(std::string_view text, const std::string& what) {
    int value = 0;
    const auto* end = text.data() + text.size();
    const auto parsed = std::from_chars(text.data(), end, value);
    if (text.empty() || parsed.ec != std::errc() || parsed.ptr != end || value < 0) {
        throw ConfigError(concat(what, " must be A:B with whole numbers 0 <= A < B, got \"", text, '"'));
    }
    return value;
}

// "A:B", "A:" or ":B" -> [A, B); B = -1 for the end
std::pair<int, int> parse_steps(const std::string& text) {
    if (text.empty()) return {0, -1};
    const auto colon = text.find(':');
    if (colon == std::string::npos) {
        throw ConfigError(concat("--steps must be A:B (e.g. 0:1000), got \"", text, '"'));
    }
    const std::string_view a(text.data(), colon), b(text.data() + colon + 1, text.size() - colon - 1);
    const int first = a.empty() ? 0 : parse_int(a, "--steps");
    const int last = b.empty() ? -1 : parse_int(b, "--steps");
    if (last != -1 && last <= first) {
        throw ConfigError(concat("--steps must be A:B with A < B, got \"", text, '"'));
    }
    return {first, last};
}

void run_render(const RenderFlags& flags) {
    // check every output before the replay
    const auto format = report::format_of(flags.out);
    const auto saliency_format =
        flags.saliency_out.empty() ? format : report::format_of(flags.saliency_out);
    for (const auto* path : {&flags.out, &flags.saliency_out}) {
        if (!path->empty() && !flags.force && std::filesystem::exists(*path)) {
            throw ConfigError(*path + " exists (use --force to replace it)");
        }
    }
    const auto [first, last] = parse_steps(flags.steps);
    if (flags.heading_every < 0) throw ConfigError(concat("--heading-every must be >= 0, got ", flags.heading_every));
    const auto stored = report::figure_kb(flags.db, flags.kb, flags.kb_name);
    if (!stored && !flags.saliency_out.empty()) {
        throw ConfigError("--saliency-out needs a knowledge base: give --kb (the run built none)");
    }
    const auto trace = report::trace_policy(flags.db, flags.individual, flags.start - 1,
                                            stored ? &stored->kb : nullptr, stored ? stored->name : "");
    if (first >= static_cast<int>(trace.steps.size())) {
        throw ConfigError(concat("--steps starts at ", first, " but start ", flags.start, " ran ", trace.steps.size(),
                                 " steps"));
    }
    report::TrajectoryOptions options;
    options.first_step = first;
    options.last_step = last;
    options.heading_every = flags.heading_every;
    const auto layout = report::ArenaLayout::fit(trace.task->arena_spec());
    report::Canvas canvas(layout.width, layout.height, format);
    report::draw_trajectory(canvas, trace, options, layout);
    canvas.save(flags.out, flags.force);
    // the steps drawn, as draw_trajectory clamps them (B is one past the last)
    const int ran = static_cast<int>(trace.steps.size());
    const int drawn_end = last < 0 ? ran : std::clamp(last, first, ran);
    std::cout << "individual " << trace.individual_id << " (generation " << trace.generation << "), start "
              << flags.start << ", " << ran << " steps run, steps " << first << " to " << drawn_end
              << " drawn (" << drawn_end - first << "), reward " << trace.reward << '\n';
    if (stored) std::cout << "knowledge base \"" << stored->name << "\": r_max " << trace.r_max << '\n';
    std::cout << "wrote " << flags.out << '\n';
    if (!flags.saliency_out.empty()) {
        report::Canvas chart(report::kFigureWidth, report::kFigureHeight, saliency_format);
        report::draw_saliency_along_time(chart, trace);
        chart.save(flags.saliency_out, flags.force);
        std::cout << "wrote " << flags.saliency_out << '\n';
    }
}

void add_render_command(CLI::App& app) {
    auto flags = std::make_shared<RenderFlags>();
    auto* cmd = app.add_subcommand(
        "render", "Draw a stored policy's trajectory in the arena, coloured by the saliency of its segments (PNG or SVG)");
    cmd->add_option("db", flags->db, "Run database (opened read-only)")->required();
    cmd->add_option("--individual", flags->individual, "'best' (default) or an individual id")
        ->check(individual_check());
    cmd->add_option("--kb", flags->kb, "KB file to colour by (default: the run's own KB, if it built one)");
    cmd->add_option("--kb-name", flags->kb_name, "Which KB of the --kb file (default: its only one)");
    cmd->add_option("--start", flags->start, "Start pose to draw, 1 to 3 (default 1, the one the KB describes)");
    cmd->add_option("--steps", flags->steps, "Step range A:B to draw (default: the whole start)");
    cmd->add_option("--heading-every", flags->heading_every, "A heading mark every N steps (default 50, 0: none)");
    cmd->add_option("--out", flags->out, "Output file, .png or .svg (SVG circles show their segment on hover)")
        ->required();
    cmd->add_option("--saliency-out", flags->saliency_out,
                    "Also draw the matched segments' average reward along time (the paper's Fig. 5), .png or .svg");
    cmd->add_flag("--force", flags->force, "Replace existing output files");
    cmd->footer(example({"stepstone render run.db --individual best --out best.png",
                         "stepstone render target.db --individual best --kb kb.db --steps 0:1000 --out best.svg",
                         "stepstone render run.db --start 2 --out start2.png --saliency-out saliency.png"}));
    cmd->callback([flags] { run_render(*flags); });
}

const CommandRegistrar render_registrar(62, add_render_command);

}  // namespace

}  // namespace stepstone::app
