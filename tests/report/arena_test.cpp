// The arena figure puts wall pixels exactly where the geometry puts walls.

#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "images.hpp"
#include "report/arena_figure.hpp"
#include "report/trace.hpp"
#include "sim/units.hpp"

using namespace stepstone;
using namespace stepstone::report;
using reporttest::Rgb;
using reporttest::rgb;

namespace {

reporttest::Image draw(const sim::Task& task, bool door_open, const ArenaLayout& layout) {
    Canvas canvas(layout.width, layout.height, Format::png);
    draw_arena(canvas, task, door_open, "", layout);
    return reporttest::decode_png(canvas.finish());
}

// distance from (x, y) to the box, 0 inside
double box_distance(const sim::WallBox& w, double x, double y) {
    const double dx = std::max({w.x0 - x, 0.0, x - w.x1});
    const double dy = std::max({w.y0 - y, 0.0, y - w.y1});
    return std::hypot(dx, dy);
}

}  // namespace

TEST_CASE("wall pixels lie inside the wall boxes and floor pixels outside, in any arena", "[report]") {
    sim::TaskConfig config;  // the source task: door closed
    const bool second = GENERATE(false, true);
    if (second) {
        config.arena = std::make_shared<const sim::ArenaSpec>(sim::ArenaSpec::load(
            std::filesystem::path(STEPSTONE_SOURCE_DIR) / "examples" / "arenas" / "two_rooms.json"));
    }
    CAPTURE(config.arena_spec().name);
    const auto task = sim::make_task(config);
    const ArenaLayout layout = ArenaLayout::fit(config.arena_spec());
    const auto image = draw(*task, false, layout);
    const auto walls = task->arena().walls();
    const auto pixel = [&](double x, double y) {
        return image.at(static_cast<int>(std::floor(layout.px(x))), static_cast<int>(std::floor(layout.py(y))));
    };

    // inside: each box's centre and points a third of the way in from its corners
    for (std::size_t i = 0; i < walls.size(); ++i) {
        const auto& w = walls[i];
        CAPTURE(i, w.x0, w.y0, w.x1, w.y1);
        const Rgb expected = static_cast<int>(i) == task->arena().door_index() ? rgb(kDoor) : rgb(kWall);
        for (const auto& [fx, fy] : {std::pair{0.5, 0.5}, {0.34, 0.34}, {0.66, 0.66}, {0.34, 0.66}, {0.66, 0.34}}) {
            const double x = w.x0 + fx * (w.x1 - w.x0), y = w.y0 + fy * (w.y1 - w.y0);
            // only where the box is more than a pixel thick around the point
            if (box_distance({w.x0 + 1.5, w.y0 + 1.5, w.x1 - 1.5, w.y1 - 1.5, ""}, x, y) > 0) continue;
            CHECK(pixel(x, y) == expected);
        }
    }

    // outside: random floor points clear of every wall, light, start pose and the basket
    const sim::Basket& basket = task->basket();
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> ux(0.0, 600.0), uy(0.0, 400.0);
    int floor_points = 0;
    for (int k = 0; k < 4000 && floor_points < 300; ++k) {
        const double x = ux(rng), y = uy(rng);
        bool clear = true;
        for (const auto& w : walls) clear = clear && box_distance(w, x, y) > 3.0;
        for (const auto& light : task->lights()) clear = clear && std::hypot(light.x - x, light.y - y) > 14.0;
        for (int s = 0; s < 3; ++s) {
            const auto& pose = task->start_pose(s);
            clear = clear && std::hypot(pose.x - x, pose.y - y) > 2.0 * sim::kRobotRadius;
        }
        clear = clear && std::hypot(basket.centre.x - x, basket.centre.y - y) > basket.radius + 3.0;
        if (!clear) continue;
        CAPTURE(x, y);
        CHECK(pixel(x, y) == rgb(kFloor));
        ++floor_points;
    }
    CHECK(floor_points == 300);
}

TEST_CASE("an open door is drawn as an outline: its inside is floor", "[report]") {
    sim::TaskConfig config;
    config.kind = sim::TaskKind::target;  // the door is open throughout
    const auto task = sim::make_task(config);
    const ArenaLayout layout;
    const auto& door = task->arena().walls()[static_cast<std::size_t>(task->arena().door_index())];
    const double x = (door.x0 + door.x1) / 2, y = (door.y0 + door.y1) / 2;
    const auto open = draw(*task, true, layout);
    const auto closed = draw(*task, false, layout);
    const int px = static_cast<int>(layout.px(x)), py = static_cast<int>(layout.py(y));
    CHECK(open.at(px, py) == rgb(kFloor));
    CHECK(closed.at(px, py) == rgb(kDoor));
}

TEST_CASE("a trajectory draws the balls as its last step left them: a taken ball is an outline", "[report]") {
    sim::TaskConfig config;  // the source task: every ball on the floor at the start
    auto task = std::shared_ptr<const sim::Task>(sim::make_task(config));
    const auto lights = task->lights();
    std::size_t ball = lights.size();
    for (std::size_t i = 0; i < lights.size() && ball == lights.size(); ++i) {
        if (lights[i].kind == sim::LightKind::ball && ((task->initial_lit() >> i) & 1u)) ball = i;
    }
    REQUIRE(ball < lights.size());
    // one step far from the ball, after which that ball is no longer lit (taken)
    Trace trace;
    trace.task = task;
    const auto pose = task->start_pose(0);
    trace.steps.push_back(
        {0, pose.x, pose.y, pose.heading, true, false, task->initial_lit() & ~(1u << ball)});
    const ArenaLayout layout;
    Canvas canvas(layout.width, layout.height, Format::png);
    draw_trajectory(canvas, trace, {}, layout);
    const auto image = reporttest::decode_png(canvas.finish());
    const int px = static_cast<int>(layout.px(lights[ball].x)),
              py = static_cast<int>(layout.py(lights[ball].y));
    CHECK(image.at(px, py) != rgb(kBall));  // its inside is floor: the ball is gone
    CHECK(image.at(px, py) == rgb(kFloor));
    // a ball still lit is drawn filled
    std::size_t other = lights.size();
    for (std::size_t i = 0; i < lights.size(); ++i) {
        if (i != ball && lights[i].kind == sim::LightKind::ball && ((task->initial_lit() >> i) & 1u))
            other = i;
    }
    REQUIRE(other < lights.size());
    CHECK(image.at(static_cast<int>(layout.px(lights[other].x)),
                   static_cast<int>(layout.py(lights[other].y))) == rgb(kBall));
}
