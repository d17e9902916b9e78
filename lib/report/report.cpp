// stepstone report: the figures, tables and provenance of a run or a campaign.

#include "report/report.hpp"

#include <algorithm>
#include <cstdio>

#include "core/error.hpp"
#include "core/output_file.hpp"
#include "core/text.hpp"
#include "core/version.hpp"
#include "db/database.hpp"
#include "db/digest.hpp"
#include "db/inspect.hpp"
#include "report/arena_figure.hpp"
#include "report/chart.hpp"
#include "report/event_figures.hpp"
#include "report/figures.hpp"
#include "report/html.hpp"
#include "report/sections.hpp"
#include "runs/evolve_config.hpp"
#include "runs/kb_stats.hpp"
#include "runs/run_store.hpp"

namespace stepstone::report {

namespace fs = std::filesystem;

std::string fixed(double value, int decimals) {
    char text[32];
    std::snprintf(text, sizeof text, "%.*f", decimals, value);
    return text;
}

std::vector<std::size_t> sample_indices(std::size_t size, std::size_t rows) {
    std::vector<std::size_t> out;
    if (size == 0) return out;
    const std::size_t stride = std::max<std::size_t>(1, (size - 1) / std::max<std::size_t>(rows, 1));
    for (std::size_t i = 0; i < size; i += stride) out.push_back(i);
    if (out.back() != size - 1) out.push_back(size - 1);
    return out;
}

void add_kb_section(Page& page, const std::string& prefix, const db::StoredKb& stored, const std::string& origin) {
    const auto stats = runs::compute_kb_stats(stored.kb);
    page.heading(concat("Knowledge base \"", stored.name, "\""), 3);
    page.table({"fact", "value"},
               {{"from", origin},
                {"segments", std::to_string(stats.segments)},
                {"segment width (steps) x channels", concat(stats.params.segment_width, " x ", stats.params.channels)},
                {"delta", fixed(stats.params.delta, 4)},
                {"match rule", db::to_string(stats.params.match)},
                {"largest average reward", fixed(stats.max_average, 4)},
                {"observations (sum of counts)", std::to_string(stats.observations)},
                {"segments seen once", std::to_string(stats.count_one)},
                {"randomized", stored.randomized_seed ? concat("yes, seed ", *stored.randomized_seed) : "no"},
                {"content digest", db::kb_digest(stored.kb, stored.randomized_seed)}});
    std::vector<std::vector<std::string>> sources;
    for (const auto& s : stats.sources) {
        sources.push_back({s.run, concat(s.first_generation, "-", s.last_generation), std::to_string(s.policies)});
    }
    if (!sources.empty()) page.table({"source run", "generations", "policies observed"}, sources, "provenance");
    page.figure(prefix + "kb-histogram", kFigureWidth, kFigureHeight,
                concat("Segments of KB \"", stored.name,
                       "\" by average reward (the paper's Fig. 3): most segments come from policies that scored "
                       "nothing, the salient ones sit on the right."),
                [&](Canvas& c) { draw_kb_histogram(c, stored.kb, concat("Knowledge base \"", stored.name, "\": segments by average reward")); });
    const auto zero = static_cast<std::size_t>(std::count_if(stored.kb.records().begin(), stored.kb.records().end(),
                                                             [](const auto& r) { return !(r.average() > 0.0); }));
    if (zero > 0 && zero < stored.kb.size()) {
        page.figure(prefix + "kb-histogram-nonzero", kFigureWidth, kFigureHeight,
                    concat("The same without the ", zero, " segments whose average reward is 0 (",
                           fixed(100.0 * static_cast<double>(zero) / static_cast<double>(stored.kb.size()), 1),
                           " % of the KB): the ", stored.kb.size() - zero, " segments seen in policies that scored."),
                    [&](Canvas& c) {
                        draw_kb_histogram(c, stored.kb,
                                          concat("Knowledge base \"", stored.name, "\": segments with a non-zero average"),
                                          25, true);
                    });
    }
    page.figure(prefix + "kb-growth", kFigureWidth, kFigureHeight,
                concat("Size of KB \"", stored.name, "\" after each observed generation."),
                [&](Canvas& c) { draw_kb_growth(c, stored.kb, concat("Knowledge base \"", stored.name, "\": growth")); });
}

void write_index(const Page& page, const fs::path& dir, ReportSummary& summary) {
    OutputFile index(dir / "index.html", false);
    index.stream() << page.html();
    index.commit();
    summary.files = page.files();
    summary.files.push_back("index.html");
}

void add_trajectory(Page& page, const std::string& name, const Trace& trace, const std::string& what) {
    const ArenaLayout layout = ArenaLayout::fit(trace.task->arena_spec());
    TrajectoryOptions options;
    page.figure(name, layout.width, layout.height,
                concat(what, ": individual ", trace.individual_id, " (generation ", trace.generation, "), start ",
                       trace.start + 1, ", reward ", fixed(trace.reward, 3),
                       trace.has_kb() ? concat(". Circles: the average reward of the KB segment matched at each step "
                                               "(white: 0 or no segment within delta), as the paper's Fig. 4 and 8; "
                                               "hover a circle for its segment.")
                                      : std::string(". No knowledge base: circles are white.")),
                [&](Canvas& c) { draw_trajectory(c, trace, options, layout); }, true);
    if (trace.has_kb()) {
        page.figure(name + "-saliency", kFigureWidth, kFigureHeight,
                    concat("Average reward of the KB segment matched by each segment of that policy along time "
                           "(the paper's Fig. 5); r_max = ", fixed(trace.r_max, 4), "."),
                    [&](Canvas& c) { draw_saliency_along_time(c, trace); });
    }
}

namespace {

// the run digest; for a file older than this program, why there is none
std::string digest_or_reason(db::Connection& connection) {
    const int version = db::database_info(connection).schema_version;
    if (version < db::latest_schema_version()) {
        return concat("none: schema version ", version, " (stepstone db migrate the file to compute it)");
    }
    return db::run_digest(connection);
}

void run_report(const ReportOptions& options, const fs::path& dir, ReportSummary& summary) {
    auto connection = db::open_database(options.input, db::OpenMode::read_only);
    const auto run = runs::load_run(connection);
    const auto generations = runs::load_generations(connection, run.id);
    if (generations.empty()) {
        throw DataError(concat(options.input.string(), ": the run has no generation yet, nothing to report"));
    }
    const auto config = runs::EvolveConfig::from_json(
        run.config, options.input.filename().string() + " (stored config)", {}, runs::ConfigOrigin::stored);
    const auto task = sim::make_task(config.task);
    const std::string file = options.input.filename().string();
    Progress progress("report", 5, options.progress);

    Page page(dir, concat("stepstone report: ", file));
    page.paragraph(concat("A ", xml_escape(run.task), "-task run, treatment <b>", xml_escape(run.treatment),
                          "</b>, seed ", run.seed, ": generation ", run.generations_done, " of ",
                          run.generations, " (", xml_escape(std::string(runs::to_string(run.status))),
                          "), best task reward ", fixed(generations.back().best, 4), " (",
                          static_cast<int>(generations.back().best * task->reward_divisor() + 0.5), " of ",
                          task->reward_divisor(), " balls)."));
    page.heading("Rewards");
    page.figure("rewards", kFigureWidth, kFigureHeight,
                "Best and median task reward of the survivors in each generation.",
                [&](Canvas& c) { draw_run_rewards(c, generations, concat("Task reward per generation: ", file)); });
    progress.update(1);
    if (std::any_of(generations.begin(), generations.end(),
                    [](const auto& g) { return g.mean_r_max.has_value(); })) {
        page.figure("shaping", kFigureWidth, kFigureHeight,
                    "r_max (the largest average reward of the KB segments matched by a policy) of the policies "
                    "evaluated in each generation.",
                    [&](Canvas& c) { draw_run_shaping(c, generations, concat("Shaping signal per generation: ", file)); });
    }
    if (db::has_milestones(connection)) {
        const auto counts = runs::load_milestone_counts(connection, run.id);
        page.figure(
            "milestones", kFigureWidth, kFigureHeight,
            "How far the policies get through the task: the share of each generation's evaluated policies "
            "that pressed the switch, picked a ball up, released one within the basket radius and collected "
            "one (docs/simulator.md: milestones).",
            [&](Canvas& c) { draw_run_milestones(c, counts, concat("Milestones per generation: ", file)); });
    } else {
        summary.notes.push_back(
            "the run file predates milestone recording (schema 0005): no milestone figure");
        page.paragraph(concat("<span class=\"note\">Note: ", summary.notes.back(), ".</span>"));
    }
    progress.update(2);

    page.heading("The arena and the best policy");
    page.figure("arena", ArenaLayout{}.width, ArenaLayout{}.height,
                "The arena at the start of an evaluation: walls, door, balls, switch, basket and the three "
                "start poses.",
                [&](Canvas& c) {
                    draw_arena(c, *task, task->door_starts_open(), concat("The ", run.task, " task's arena"),
                               ArenaLayout::fit(task->arena_spec()));
                });
    progress.update(3);
    const auto stored = run_kb(connection);
    const auto trace = trace_policy(connection, run, config, "best", 0, stored ? &stored->kb : nullptr,
                                    stored ? stored->name : "");
    add_trajectory(page, "trajectory", trace, "The run's best stored policy");
    progress.update(4);
    if (stored) {
        page.heading("Knowledge base");
        add_kb_section(page, "", *stored, concat("built by this run (observed every ", config.kb ? config.kb->period : 0,
                                                 " generations)"));
    } else {
        summary.notes.push_back("the run built no knowledge base: no KB figures");
    }
    progress.update(5);

    page.heading("Generations");
    std::vector<std::vector<std::string>> rows;
    for (const std::size_t i : sample_indices(generations.size(), 10)) {
        const auto& g = generations[i];
        rows.push_back({std::to_string(g.generation), fixed(g.best, 4), fixed(g.median, 4),
                        g.mean_r_max ? fixed(*g.mean_r_max, 4) : "-"});
    }
    page.table({"generation", "best reward", "median reward", "mean r_max"}, rows);
    page.heading("Provenance");
    page.table({"fact", "value"}, {{"file", options.input.string()},
                                   {"seed", std::to_string(run.seed)},
                                   {"evaluations", std::to_string(run.evaluations)},
                                   {"run digest (stepstone db digest)", digest_or_reason(connection)},
                                   {"report written by", "stepstone " + full_version()}});
    page.heading("Config", 3);
    page.preformatted(run.config.dump(2));
    progress.finish();

    write_index(page, dir, summary);
}

}  // namespace

ReportSummary write_report(const ReportOptions& options) {
    if (!(options.threshold >= 0.0 && options.threshold <= 1.0)) {
        throw ConfigError(
            concat(option_name("threshold"), " must be within [0, 1], got ", options.threshold));
    }
    std::error_code error;
    if (!fs::exists(options.input, error)) throw ConfigError(concat(options.input.string(), ": no such file or directory"));
    const bool campaign = fs::is_directory(options.input);
    if (campaign && !fs::exists(options.input / "campaign.db")) {
        throw DataError(concat(options.input.string(), ": no campaign.db here (give a run file or a campaign directory)"));
    }
    ReportSummary summary;
    write_directory(options.out, options.force, [&](const fs::path& dir) {
        if (campaign) {
            campaign_report(options, dir, summary);
        } else {
            run_report(options, dir, summary);
        }
    });
    summary.index = options.out / "index.html";
    return summary;
}

}  // namespace stepstone::report
