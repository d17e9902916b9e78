// Every figure renders as a valid, non-blank PNG of the asked size and a
// well-formed SVG, from data read out of a small run built by the test; and
// what a figure shows, read back from its pixels against hand-made data.

#include "report/figures.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <functional>

#include "core/error.hpp"
#include "db/database.hpp"
#include "runs/run_store.hpp"
#include "images.hpp"
#include "report/arena_figure.hpp"
#include "report/chart.hpp"
#include "runs.hpp"
#include "sim/task.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using namespace stepstone::report;
using reporttest::check_png;
using reporttest::check_svg;

namespace {

void check_figure(const std::string& name, int width, int height, const std::function<void(Canvas&)>& draw) {
    CAPTURE(name);
    Canvas png(width, height, Format::png);
    draw(png);
    CHECK(check_png(png.finish(), width, height).empty());
    Canvas svg(width, height, Format::svg);
    draw(svg);
    CHECK(check_svg(svg.finish()).empty());
}

// a campaign's statistics made by hand: two treatments, three runs each
runs::CampaignStats hand_stats() {
    runs::CampaignStats stats;
    stats.generation = 4;
    stats.threshold = 0.5;
    const std::vector<std::vector<double>> curves{{0, 0, 0.25, 0.5, 0.5},   {0, 0.1, 0.1, 0.1, 0.6},
                                                  {0, 0, 0, 0, 0.2},        {0, 0, 0, 0, 0},
                                                  {0, 0.05, 0.05, 0.1, 0.1}, {0, 0, 0, 0, 0.05}};
    for (std::size_t r = 0; r < curves.size(); ++r) {
        const auto t = r < 3 ? runs::Treatment::sum : runs::Treatment::none;
        runs::RunCurve run;
        run.treatment = t;
        run.seed = r % 3 + 1;
        run.file = "f";
        run.best = curves[r];
        stats.runs.push_back(run);
    }
    for (const auto t : {runs::Treatment::sum, runs::Treatment::none}) {
        runs::TreatmentResult result;
        result.treatment = t;
        for (const auto& run : stats.runs) {
            if (run.treatment == t) result.best.push_back(run.best.back());
        }
        result.summary = stats::summarize(result.best);
        result.successes = stats::count_at_least(result.best, 0.5);
        stats.treatments.push_back(result);
    }
    for (std::size_t g = 0; g <= 4; ++g) {
        std::vector<std::size_t> row{0, 0};
        for (std::size_t r = 0; r < curves.size(); ++r) row[r < 3 ? 0 : 1] += curves[r][g] >= 0.5;
        stats.successes.push_back(row);
    }
    return stats;
}

}  // namespace

TEST_CASE("every figure renders as PNG and SVG from a small run", "[report]") {
    test::TempDir dir;
    reporttest::make_run(dir / "run.db");
    auto connection = db::open_database(dir / "run.db", db::OpenMode::read_only);
    const auto run = runs::load_run(connection);
    const auto generations = runs::load_generations(connection, run.id);
    REQUIRE(generations.size() == 5);  // generations 0 to 4
    const auto stored = figure_kb(dir / "run.db", "");
    REQUIRE(stored.has_value());
    REQUIRE(stored->kb.size() > 0);
    const auto trace = trace_policy(dir / "run.db", "best", 0, &stored->kb, stored->name);
    const ArenaLayout layout;

    check_figure("rewards", kFigureWidth, kFigureHeight, [&](Canvas& c) { draw_run_rewards(c, generations, "r"); });
    check_figure("histogram", kFigureWidth, kFigureHeight, [&](Canvas& c) { draw_kb_histogram(c, stored->kb, "h"); });
    check_figure("growth", kFigureWidth, kFigureHeight, [&](Canvas& c) { draw_kb_growth(c, stored->kb, "g"); });
    check_figure("saliency", kFigureWidth, kFigureHeight, [&](Canvas& c) { draw_saliency_along_time(c, trace); });
    check_figure("arena", layout.width, layout.height,
                 [&](Canvas& c) { draw_arena(c, *trace.task, false, "arena", layout); });
    check_figure("trajectory", layout.width, layout.height,
                 [&](Canvas& c) { draw_trajectory(c, trace, {}, layout); });

    const auto stats = hand_stats();
    check_figure("successes", kFigureWidth, kFigureHeight, [&](Canvas& c) { draw_successes(c, stats); });
    check_figure("best-of-run", kFigureWidth, kFigureHeight, [&](Canvas& c) { draw_best_of_run(c, stats); });
    check_figure("treatment rewards", kFigureWidth, kFigureHeight,
                 [&](Canvas& c) { draw_treatment_rewards(c, stats); });
    // the run's own r_max values are NULL (a source run); give two runs some
    std::vector<GenerationPoint> shaped = generations;
    for (std::size_t g = 0; g < shaped.size(); ++g) shaped[g].mean_r_max = 0.1 * static_cast<double>(g);
    const std::vector<std::vector<std::vector<GenerationPoint>>> series{{shaped, shaped}};
    const runs::Treatment treatments[] = {runs::Treatment::sum};
    check_figure("treatment shaping", kFigureWidth, kFigureHeight,
                 [&](Canvas& c) { draw_treatment_shaping(c, treatments, series); });
    check_figure("treatment medians", kFigureWidth, kFigureHeight,
                 [&](Canvas& c) { draw_treatment_medians(c, treatments, series); });
    check_figure("run shaping", kFigureWidth, kFigureHeight, [&](Canvas& c) { draw_run_shaping(c, shaped, "s"); });
}

TEST_CASE("a figure's file name decides its format, and others are refused", "[report]") {
    CHECK(format_of("a/b.png") == Format::png);
    CHECK(format_of("B.SVG") == Format::svg);
    CHECK_THROWS_WITH(format_of("plot.jpg"), "plot.jpg: the figure's file name must end in .png or .svg");
    CHECK_THROWS_AS(format_of("plot"), ConfigError);
}

TEST_CASE("a histogram's bars are as tall as the counts say", "[report]") {
    // three segments: averages 0, 0 and 1 (largest 1): the first bin holds 2,
    // the last 1, so the first bar is twice the last one's height
    kb::KbParams params;
    params.segment_width = 1;
    params.channels = 1;
    params.delta = 0.5;
    kb::KnowledgeBase base(params);
    const auto source = base.add_source("t");
    const float values[] = {0.0f, 2.0f, 4.0f};
    const double rewards[] = {0.0, 0.0, 1.0};
    for (int i = 0; i < 3; ++i) base.observe(kb::as_segments({&values[i], 1}, 1), rewards[i], {source, 0});
    Canvas canvas(kFigureWidth, kFigureHeight, Format::png);
    draw_kb_histogram(canvas, base, "", 4);
    const auto image = reporttest::decode_png(canvas.finish());
    // scan the columns in the middle of the first and last bins for the bar colour
    const auto bar_height = [&](double fraction) {
        int height = 0;
        int x = -1;
        // the plot spans the canvas width minus the margins; find the bins by colour
        for (int cx = 0; cx < image.width; ++cx) {
            int h = 0;
            for (int y = 0; y < image.height; ++y) h += image.at(cx, y) == reporttest::Rgb{0x00, 0x72, 0xB2};
            if (h > 0 && x < 0 && fraction < 0.5) {
                x = cx;
                height = h;
            }
            if (h > 0 && fraction > 0.5) height = h;  // the last column with ink
        }
        return height;
    };
    const int first = bar_height(0.0);
    const int last = bar_height(1.0);
    REQUIRE(last > 10);
    CHECK(std::abs(first - 2 * last) <= 2);
}

TEST_CASE("a line chart's legend goes to the corner its curves leave free", "[report]") {
    // three curves high (0.9) from the left to x = 9, then down to 0 at x = 10: the top corners are
    // taken, the bottom ones free; the legend used to sit at the top left, over the curves
    std::vector<Curve> curves;
    const Colour colours[] = {kBlue, kVermillion, kGreen};
    for (int k = 0; k < 3; ++k) {
        Curve c{"curve " + std::to_string(k), colours[k], {}, {}, {}, {}, false, false};
        for (int x = 0; x <= 10; ++x) {
            c.x.push_back(x);
            c.y.push_back(x < 10 ? 0.9 - 0.05 * k : 0.0);
        }
        curves.push_back(std::move(c));
    }
    const ChartFrame frame{"legend", "x", "y", {}, {}};
    Canvas canvas(kFigureWidth, kFigureHeight, Format::png);
    line_chart(canvas, frame, curves);
    const auto image = reporttest::decode_png(canvas.finish());
    // where the first curve is drawn at x = 1 and x = 9, by the same axes as line_chart's
    Canvas probe_canvas(kFigureWidth, kFigureHeight, Format::png);
    const Chart probe(probe_canvas, frame, 0.0, 10.0, 0.0, 0.9);
    const reporttest::Rgb blue{0x00, 0x72, 0xB2};
    for (const double x : {1.0, 9.0}) {
        const int px = static_cast<int>(probe.px(x)), py = static_cast<int>(probe.py(0.9));
        bool pure = false;  // the line's own colour, not washed out by the legend's white box
        for (int dy = -2; dy <= 2; ++dy) pure = pure || image.at(px, py + dy) == blue;
        CAPTURE(x, px, py);
        CHECK(pure);
    }
}

TEST_CASE("a curve drawn exactly over another says so in the legend", "[report]") {
    Curve sum{"sum", kBlue, {0, 1, 2}, {0, 0, 0}, {}, {}, false, false};
    Curve mo{"mo", kVermillion, {0, 1, 2}, {0, 0, 0}, {}, {}, false, false};
    Curve other{"none", kGreen, {0, 1, 2}, {0, 0.5, 0}, {}, {}, false, false};
    const std::vector<Curve> curves = {sum, mo, other};
    const auto entries = legend_entries(curves);
    REQUIRE(entries.size() == 3);
    CHECK(entries[0].first == "sum");
    CHECK(entries[1].first == "mo (same line as sum)");
    CHECK(entries[2].first == "none");
}

TEST_CASE("a trajectory figure draws a known path where the arena's geometry puts it, and floor around it",
          "[report]") {
    // a hand-made trace on the paper's arena: 20 steps right along y = 235 from x = 250, then
    // 20 down along x = 360 from y = 240 (units), in the room below the horizontal wall
    sim::TaskConfig config;
    config.kind = sim::TaskKind::source;
    config.steps_per_start = 40;
    config.starts = 1;
    Trace trace;
    trace.task = sim::make_task(config);
    for (int k = 0; k < 40; ++k) {
        TraceStep step;
        step.step = k;
        step.x = k < 20 ? 250.0 + 5.0 * k : 360.0;
        step.y = k < 20 ? 235.0 : 240.0 + 5.0 * (k - 20);
        step.lit = trace.task->initial_lit();
        trace.steps.push_back(step);
    }
    // segments of 10 steps matched with averages 1, 0, 0.25 and 1 of a largest 1
    trace.segment_width = 10;
    trace.max_average = 1.0;
    const double averages[] = {1.0, 0.0, 0.25, 1.0};
    for (std::size_t i = 0; i < 4; ++i) {
        kb::SegmentMatch match;
        match.id = i;
        match.average_reward = averages[i];
        trace.segments.push_back(match);
    }
    TrajectoryOptions options;
    options.heading_every = 0;
    options.title = "a known path";
    Canvas canvas(800, 680, Format::png);
    draw_trajectory(canvas, trace, options);
    const auto image = reporttest::decode_png(canvas.finish());

    // the documented geometry (ArenaLayout in report/arena_figure.hpp: 600 units -> 750 px,
    // px = 25 + 1.25 x, py = 46 + 1.25 y, y down as in the simulator), written out here
    const auto pixel = [&](double x, double y) {
        return image.at(static_cast<int>(std::floor(25.0 + 1.25 * x)),
                        static_cast<int>(std::floor(46.0 + 1.25 * y)));
    };
    const auto near_colour = [](reporttest::Rgb a, reporttest::Rgb b) {
        return std::abs(a.r - b.r) <= 1 && std::abs(a.g - b.g) <= 1 && std::abs(a.b - b.b) <= 1;
    };
    // the saliency ramp by hand: white to #08306B; a quarter of the way is
    // 255 + (0x08 - 255) / 4 = 193.25, 255 + (0x30 - 255) / 4 = 203.25, 255 + (0x6B - 255) / 4 = 218
    const reporttest::Rgb by_segment[] = {
        {0x08, 0x30, 0x6B}, {255, 255, 255}, {193, 203, 218}, {0x08, 0x30, 0x6B}};
    for (const auto& step : trace.steps) {
        const auto seen = pixel(step.x, step.y);
        const auto expected = by_segment[step.step / 10];
        CAPTURE(step.step, step.x, step.y, seen.r, seen.g, seen.b, expected.r, expected.g, expected.b);
        CHECK(near_colour(seen, expected));
    }
    // the floor (#F2F2F2) stays bare beside the path (6 units off it), where the path would
    // lie with x and y swapped, and between the legs
    const reporttest::Rgb floor_colour{0xF2, 0xF2, 0xF2};
    const std::pair<double, double> bare[] = {{300, 229}, {300, 241}, {354, 300}, {366, 300},
                                              {235, 300}, {300, 360}, {310, 265}};
    for (const auto& [x, y] : bare) {
        const auto seen = pixel(x, y);
        CAPTURE(x, y, seen.r, seen.g, seen.b);
        CHECK(seen == floor_colour);
    }
}
