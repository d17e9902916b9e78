// The trajectory's circles are coloured by the matched segments' rewards,
// computed here from the KB by brute force, not by the renderer's lookup.

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <set>

#include "core/error.hpp"
#include "db/database.hpp"
#include "images.hpp"
#include "kb/segments.hpp"
#include "report/arena_figure.hpp"
#include "runs.hpp"
#include "runs/replay.hpp"
#include "sim/sensors.hpp"
#include "support/temp_dir.hpp"

using namespace stepstone;
using namespace stepstone::report;
using reporttest::Rgb;

namespace {

constexpr std::size_t kChannels = 15;

// a KB of the policy's own segments, each observed with a reward of its own:
// segment i with reward (i % 4) / 3 (identical segments merge, mixing rewards)
kb::KnowledgeBase own_kb(const std::vector<float>& behaviour, double delta) {
    kb::KbParams params;
    params.segment_width = reporttest::kWidth;
    params.channels = kChannels;
    params.delta = delta;
    kb::KnowledgeBase base(params);
    const auto source = base.add_source("test");
    const auto segments = kb::segment_behaviour(behaviour, kChannels, reporttest::kWidth);
    for (std::size_t i = 0; i < segments.size(); ++i) {
        base.observe(kb::as_segments(segments[i], params.dim()), static_cast<double>(i % 4) / 3.0, {source, 0});
    }
    return base;
}

// the average reward credited to `segment`: the nearest KB segment by a plain
// loop over every stored value, if closer than delta; else 0
double oracle_average(const kb::KnowledgeBase& base, std::span<const float> segment) {
    const std::size_t dim = base.params().dim();
    double best = std::numeric_limits<double>::infinity();
    std::size_t best_id = 0;
    for (std::size_t id = 0; id < base.size(); ++id) {
        double sum = 0.0;
        for (std::size_t k = 0; k < dim; ++k) {
            const double d = static_cast<double>(base.values()[id * dim + k]) - static_cast<double>(segment[k]);
            sum += d * d;
        }
        if (std::sqrt(sum) < best) {
            best = std::sqrt(sum);
            best_id = id;
        }
    }
    return best < base.params().delta ? base.record(best_id).average() : 0.0;
}

// white (255) to 0x08306B, linear in each channel, rounded to a byte
Rgb expected_colour(double t) {
    return {static_cast<int>(std::lround(255.0 + (0x08 - 255.0) * t)),
            static_cast<int>(std::lround(255.0 + (0x30 - 255.0) * t)),
            static_cast<int>(std::lround(255.0 + (0x6B - 255.0) * t))};
}

// steps of `trace` whose circle centre no later circle covers (within r + 1.5 px)
std::vector<std::size_t> visible_steps(const Trace& trace, const ArenaLayout& layout, double r) {
    std::vector<std::size_t> out;
    for (std::size_t k = 0; k < trace.steps.size(); ++k) {
        const double x = std::floor(layout.px(trace.steps[k].x)) + 0.5;
        const double y = std::floor(layout.py(trace.steps[k].y)) + 0.5;
        bool covered = false;
        for (std::size_t j = k + 1; j < trace.steps.size() && !covered; ++j) {
            covered = std::hypot(layout.px(trace.steps[j].x) - x, layout.py(trace.steps[j].y) - y) < r + 1.5;
        }
        if (!covered) out.push_back(k);
    }
    return out;
}

// the stored individual whose first start leaves the most circles in view
std::string moving_individual(const std::filesystem::path& run, const ArenaLayout& layout, double r) {
    auto connection = db::open_database(run, db::OpenMode::read_only);
    auto ids = connection.prepare("SELECT individual_id FROM genome ORDER BY individual_id");
    std::string best;
    std::size_t most = 0;
    while (ids.step()) {
        const auto id = std::to_string(ids.column_int(0));
        const auto visible = visible_steps(trace_policy(run, id, 0, nullptr), layout, r).size();
        if (visible > most) {
            most = visible;
            best = id;
        }
    }
    return best;
}

bool close(const Rgb& a, const Rgb& b) {
    return std::abs(a.r - b.r) <= 1 && std::abs(a.g - b.g) <= 1 && std::abs(a.b - b.b) <= 1;
}

}  // namespace

TEST_CASE("trajectory circles take the colour of their segment's KB average", "[report]") {
    test::TempDir dir;
    reporttest::make_run(dir / "run.db", true);
    const ArenaLayout layout;
    TrajectoryOptions options;
    options.heading_every = 0;  // no heading marks over the circles
    const double r = options.circle_radius * layout.scale;
    const auto individual = moving_individual(dir / "run.db", layout, r);
    // the behaviour as evolve records it (runs::replay_behaviour), to build the KB
    const auto behaviour = runs::replay_behaviour(dir / "run.db", individual);
    REQUIRE(behaviour.size() == reporttest::kSteps * kChannels);
    const auto base = own_kb(behaviour, 0.05);
    const auto trace = trace_policy(dir / "run.db", individual, 0, &base, "own");
    // the trace's behaviour, gathered step by step, is the recorded one
    CHECK(trace.behaviour == behaviour);
    REQUIRE(trace.steps.size() == static_cast<std::size_t>(reporttest::kSteps));

    Canvas canvas(layout.width, layout.height, Format::png);
    draw_trajectory(canvas, trace, options, layout);
    const auto image = reporttest::decode_png(canvas.finish());

    const auto segments = kb::segment_behaviour(behaviour, kChannels, reporttest::kWidth);
    const double max_average = [&] {
        double m = 0.0;
        for (const auto& record : base.records()) m = std::max(m, record.average());
        return m;
    }();
    REQUIRE(max_average > 0.0);
    int checked = 0;
    std::set<int> shades;
    for (const std::size_t k : visible_steps(trace, layout, r)) {
        const auto& step = trace.steps[k];
        const int px = static_cast<int>(std::floor(layout.px(step.x)));
        const int py = static_cast<int>(std::floor(layout.py(step.y)));
        const double average = oracle_average(base, segments[k / reporttest::kWidth]);
        const Rgb expected = expected_colour(average / max_average);
        CAPTURE(k, average, expected.r, expected.g, expected.b);
        const Rgb seen = image.at(px, py);
        CAPTURE(seen.r, seen.g, seen.b);
        CHECK(close(seen, expected));
        ++checked;
        shades.insert(expected.r);
    }
    // enough circles, of several shades, were checked for the test to mean something
    CHECK(checked >= 10);
    CHECK(shades.size() >= 2);
}

TEST_CASE("without a knowledge base every circle is white", "[report]") {
    test::TempDir dir;
    reporttest::make_run(dir / "run.db");
    const auto trace = trace_policy(dir / "run.db", "best", 0, nullptr);
    CHECK_FALSE(trace.has_kb());
    CHECK(circle_colour(trace.match_at(0), 1.0).r == 1.0);
    kb::SegmentMatch match;
    match.id = 3;
    match.average_reward = 0.5;
    // a KB whose largest average is 0 colours nothing
    CHECK(circle_colour(match, 0.0).b == 1.0);
    CHECK(circle_colour(match, 1.0).b == Approx((255.0 + (0x6B - 255.0) * 0.5) / 255.0));
}

TEST_CASE("an SVG trajectory gives every circle a hover title naming its step and segment", "[report]") {
    test::TempDir dir;
    reporttest::make_run(dir / "run.db");
    const auto behaviour = runs::replay_behaviour(dir / "run.db", "best");
    const auto base = own_kb(behaviour, 0.05);
    const auto trace = trace_policy(dir / "run.db", "best", 0, &base, "own");
    TrajectoryOptions options;
    options.first_step = 20;
    options.last_step = 60;
    Canvas canvas(ArenaLayout{}.width, ArenaLayout{}.height, Format::svg);
    draw_trajectory(canvas, trace, options);
    const auto facts = reporttest::parse_svg(canvas.finish());
    REQUIRE(facts.well_formed);
    REQUIRE(facts.titles == 40);
    // step 20 is the first of segment 2; segments match themselves (distance 0)
    CHECK(facts.title_texts.front().rfind("step 20, segment 2, KB segment ", 0) == 0);
    CHECK(facts.title_texts.front().find("distance 0.0") != std::string::npos);
    CHECK(facts.title_texts.back().rfind("step 59, segment 5,", 0) == 0);
}

TEST_CASE("a start the evaluation never reached, or outside the task, is refused", "[report]") {
    test::TempDir dir;
    reporttest::make_run(dir / "run.db");
    CHECK_THROWS_WITH(trace_policy(dir / "run.db", "best", 1, nullptr),
                      "`start` must be within 1 to 1 (the run's starts), got 2");
    CHECK_THROWS_AS(trace_policy(dir / "run.db", "best", -1, nullptr), ConfigError);
}
