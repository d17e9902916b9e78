#include "reference/fastsim_baseline.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <vector>

using namespace stepstone::reference;

namespace {

constexpr float kPi = std::numbers::pi_v<float>;
constexpr double kFx = 296.0 / 600.0;

// a robot placed at `pose` with its sensors computed there (a zero move)
BitmapRobot robot_at(BitmapPose pose, const BitmapMap& map, const std::vector<Light>& lights = {}) {
    BitmapRobot robot(pose);
    robot.move(0, 0, map, lights);
    return robot;
}

}  // namespace

TEST_CASE("the rasterised bitmap has the walls of the wall table", "[bench][fastsim]") {
    const BitmapMap closed(Door::closed);
    const BitmapMap open(Door::open);
    // lib/sim/arena.cpp gives each wall as pixel ranges (docs/original.md: arena); pixel centres are i / fx
    for (const BitmapMap* map : {&closed, &open}) {
        CHECK(map->obstacle(4, 100));     // outer left, x 0-4
        CHECK_FALSE(map->obstacle(5, 100));
        CHECK(map->obstacle(291, 50));    // outer right, x 291-295
        CHECK_FALSE(map->obstacle(290, 50));
        CHECK(map->obstacle(150, 4));     // outer top, y 0-4
        CHECK_FALSE(map->obstacle(150, 5));
        CHECK(map->obstacle(150, 195));   // arena bottom, y 195-197
        CHECK(map->obstacle(150, 197));
        CHECK_FALSE(map->obstacle(150, 194));
        CHECK_FALSE(map->obstacle(150, 198));  // the empty box below, rows 198-290
        CHECK_FALSE(map->obstacle(150, 290));
        CHECK(map->obstacle(150, 291));
        CHECK(map->obstacle(100, 50));    // divider, x 100-102
        CHECK(map->obstacle(102, 50));
        CHECK_FALSE(map->obstacle(99, 50));
        CHECK_FALSE(map->obstacle(103, 50));
        CHECK(map->obstacle(101, 126));   // divider just above the door rows 127-173
        CHECK(map->obstacle(101, 174));   // and just below
        CHECK(map->obstacle(223, 100));   // horizontal wall x 100-223, y 99-101
        CHECK(map->obstacle(150, 99));
        CHECK_FALSE(map->obstacle(150, 98));
        CHECK_FALSE(map->obstacle(224, 100));  // its gap, x 224-269
        CHECK_FALSE(map->obstacle(269, 100));
        CHECK(map->obstacle(270, 100));
        CHECK(map->obstacle(197, 110));   // upper stub x 196-198, y 102-126
        CHECK(map->obstacle(196, 126));
        CHECK_FALSE(map->obstacle(197, 127));  // gap between the stubs, y 127-173
        CHECK_FALSE(map->obstacle(197, 173));
        CHECK(map->obstacle(198, 174));   // lower stub, y 174-194
        CHECK_FALSE(map->obstacle(199, 180));
        CHECK(map->obstacle(-1, 10));     // outside the map counts as a wall
        CHECK(map->obstacle(10, 296));
    }
    // the door: divider rows 127-173 are wall only when closed
    for (int y : {127, 150, 173}) {
        CHECK(closed.obstacle(101, y));
        CHECK_FALSE(open.obstacle(101, y));
    }
}

TEST_CASE("lasers at known poses give the quantised distances to the wall pixels", "[bench][fastsim]") {
    const BitmapMap closed(Door::closed);
    const BitmapMap open(Door::open);

    // facing west in the left room from (100, 300): the ray runs along pixel
    // row 148 to the outer wall's last pixel x = 4, at world 4 / fx
    auto robot = robot_at({100, 300, kPi}, closed);
    CHECK(robot.laser(2) == Approx(100 - 4 / kFx).epsilon(1e-5));  // 91.89

    // facing east from (300, 100): the outer right wall starts at pixel 291
    robot = robot_at({300, 100, 0}, closed);
    CHECK(robot.laser(2) == Approx(291 / kFx - 300).epsilon(1e-5));  // 289.86
    // the +pi/4 laser runs the exact diagonal from pixel (148, 49); at step 50
    // the corner test sees (197, 99), the horizontal wall, and reports the
    // line pixel (198, 99)
    CHECK(robot.laser(0) == Approx(std::hypot(198 / kFx - 300, 99 / kFx - 100)).epsilon(1e-5));  // 142.86

    // facing east from (220, 100) the wall at 589.9 is 370 away: out of range
    robot = robot_at({220, 100, 0}, closed);
    CHECK(robot.laser(2) == -1.0f);
    float in[11];
    robot.sensor_inputs(in);
    CHECK(in[2] == 0.0f);

    // facing east from (150, 300) the closed door is the divider's pixel 100;
    // open, the ray passes the door and the stub gap and ends out of range
    robot = robot_at({150, 300, 0}, closed);
    CHECK(robot.laser(2) == Approx(100 / kFx - 150).epsilon(1e-5));  // 52.70
    robot.sensor_inputs(in);
    CHECK(in[2] == Approx(1 - (100 / kFx - 150) / 320).epsilon(1e-5));
    robot = robot_at({150, 300, 0}, open);
    CHECK(robot.laser(2) == -1.0f);
}

TEST_CASE("light sensors see lit lights of their colour in their window and in sight", "[bench][fastsim]") {
    const BitmapMap closed(Door::closed);
    const BitmapMap open(Door::open);
    // a ball straight ahead lies in both windows (their 0.01 rad overlap)
    std::vector<Light> lights{{400, 100, LightColor::ball, true}};
    auto robot = robot_at({300, 100, 0}, closed, lights);
    CHECK(robot.light(0));
    CHECK(robot.light(1));
    CHECK_FALSE(robot.light(2));  // basket sensors ignore balls
    // 60 degrees to the right (y down: +angle) is only in the +pi/4 window
    lights[0] = {300 + 100 * std::cos(kPi / 3), 100 + 100 * std::sin(kPi / 3), LightColor::ball, true};
    robot = robot_at({300, 100, 0}, closed, lights);
    CHECK(robot.light(0));
    CHECK_FALSE(robot.light(1));
    // an unlit light is ignored
    lights[0].on = false;
    robot = robot_at({300, 100, 0}, closed, lights);
    CHECK_FALSE(robot.light(0));
    // behind the robot: no sensor
    lights[0] = {200, 100, LightColor::button, true};
    robot = robot_at({300, 100, 0}, closed, lights);
    CHECK_FALSE(robot.light(4));
    CHECK_FALSE(robot.light(5));
    // a light in the left room, seen from the main room through the door only
    lights[0] = {100, 300, LightColor::basket, true};
    robot = robot_at({300, 300, kPi}, closed, lights);
    CHECK_FALSE(robot.light(2));
    CHECK_FALSE(robot.light(3));
    robot = robot_at({300, 300, kPi}, open, lights);
    CHECK(robot.light(2));
    CHECK(robot.light(3));
}

TEST_CASE("driving into a wall keeps the position, sets the sticky flag and the bumpers", "[bench][fastsim]") {
    const BitmapMap map(Door::closed);
    const std::vector<Light> lights;

    // straight west from x = 31 (pixel 15, 11 px from the wall's pixel 4) to
    // x = 27 (pixel 13): wall pixels within rp = 10 px on both sides of the
    // heading, so both bumpers
    BitmapRobot robot({31, 100, kPi});
    robot.move(4, 4, map, lights);
    CHECK(robot.pose().x == 31.0f);
    CHECK(robot.pose().y == 100.0f);
    CHECK(robot.collision());
    CHECK(robot.left_bumper());
    CHECK(robot.right_bumper());

    // heading pi - 0.5 the attempted centre is pixel (14, 50); the only contact
    // is (4, 50), at a = pi - (pi - 0.5) = 0.5: the (0, pi/2) bumper alone
    robot = BitmapRobot({31, 100, kPi - 0.5f});
    robot.move(4, 4, map, lights);
    CHECK(robot.pose().x == 31.0f);
    CHECK(robot.left_bumper());
    CHECK_FALSE(robot.right_bumper());

    // an arc into the wall is blocked but the heading turns by (4 - 3) / 40
    robot = BitmapRobot({31, 100, kPi});
    robot.move(3, 4, map, lights);
    CHECK(robot.pose().x == 31.0f);
    CHECK(robot.pose().theta == Approx(normalize_angle(kPi + 0.025f)));

    // moving away clears the bumpers but not the sticky flag
    robot.move(-4, -4, map, lights);
    CHECK(robot.pose().x > 31.0f);
    CHECK_FALSE(robot.left_bumper());
    CHECK_FALSE(robot.right_bumper());
    CHECK(robot.collision());
    robot.reinit();
    CHECK_FALSE(robot.collision());
}

TEST_CASE("full speed into a wall never tunnels through it", "[bench][fastsim]") {
    const BitmapMap map(Door::closed);
    // 400 steps east at 4 units per step would cross the divider (x 201.7-207.8)
    BitmapRobot robot({100, 50, 0});
    for (int k = 0; k < 400; ++k) robot.move(4, 4, map, {});
    CHECK(robot.pose().x < 201.7f - 20);
    CHECK(robot.collision());
}

TEST_CASE("arc odometry matches the differential-drive formulas", "[bench][fastsim]") {
    // straight: d along the heading
    auto p = arc_move({100, 100, 0}, 4, 4);
    CHECK(p.x == Approx(104));
    CHECK(p.y == Approx(100));
    // on the spot: alpha = (4 - (-4)) / 40 = 0.2, arc radius -4 / 0.2 + 20 = 0
    p = arc_move({100, 100, 0}, -4, 4);
    CHECK(p.x == Approx(100));
    CHECK(p.y == Approx(100));
    CHECK(p.theta == Approx(0.2));
    // one wheel still: alpha = 0.1, radius 20, centre displacement
    // (20 sin 0.1, 20 (1 - cos 0.1)) from heading 0 (y down)
    p = arc_move({100, 100, 0}, 0, 4);
    CHECK(p.x == Approx(100 + 20 * std::sin(0.1)));
    CHECK(p.y == Approx(100 + 20 * (1 - std::cos(0.1))));
    CHECK(p.theta == Approx(0.1));
}

namespace {

struct StillController {
    void reset() {}
    void step(const float*, float* out) {
        out[0] = 0.5f;
        out[1] = 0.5f;
        out[2] = 0.0f;
    }
};

}  // namespace

TEST_CASE("a controller that stands still ends the evaluation after 101 still steps", "[bench][fastsim]") {
    const BitmapArena arena;
    BitmapCollectBall episode(arena, BitmapTask::source);
    StillController controller;
    std::vector<float> behaviour(4000 * 15, -1.0f);
    std::vector<std::int32_t> cells(160, -1);
    const auto result = run_bitmap_episode(episode, controller, {behaviour, cells});
    // wheels 4 (2 * 0.5 - 1) = 0: every step is still; the 101st passes 100
    CHECK(result.steps == 101);
    CHECK(result.stopped);
    CHECK(result.collected == 0);
    // start 1 at (296.25, 101.25): cell (5, 2) for every sample, recorded or padded
    for (int k = 0; k < 80; ++k) {
        CHECK(cells[static_cast<std::size_t>(2 * k)] == 5);
        CHECK(cells[static_cast<std::size_t>(2 * k + 1)] == 2);
    }
    // the behaviour rows of the steps run hold the outputs
    CHECK(behaviour[100 * 15 + 12] == 0.5f);
    CHECK(behaviour[101 * 15 + 12] == -1.0f);
}

TEST_CASE("a release scores only pressed against the bottom wall near the basket", "[bench][fastsim]") {
    const BitmapArena arena;
    BitmapCollectBall episode(arena, BitmapTask::source);
    episode.reset();
    episode.begin_start(0);
    float in[12] = {};
    const float drive_down[3] = {1.0f, 1.0f, 1.0f};
    const float release[3] = {0.5f, 0.5f, 0.0f};

    // (296.25, 372) is 33 from the basket centre (296.25, 405), within 33.75;
    // its pixel row 184 is 11 px from the wall's row 195, one more 4-unit step
    // down reaches row 185, within rp = 10: a collision
    episode.place({296.25f, 372, kPi / 2});
    episode.set_carrying(true);
    // a release before any collision loses the ball
    REQUIRE(episode.apply(1, in, release, {}));
    CHECK_FALSE(episode.carrying());
    CHECK(episode.collected() == 0);

    episode.set_carrying(true);
    REQUIRE(episode.apply(2, in, drive_down, {}));
    CHECK(episode.robot().collision());
    CHECK(episode.robot().pose().y == 372.0f);
    REQUIRE(episode.apply(3, in, release, {}));
    CHECK(episode.collected() == 1);
    CHECK(episode.finish(4, {}).reward == Approx(1.0 / 24));

    // with the sticky flag still set, a release far from the basket loses the ball
    episode.place({300, 300, 0});
    episode.set_carrying(true);
    REQUIRE(episode.apply(4, in, release, {}));
    CHECK(episode.collected() == 1);
}

TEST_CASE("grabbing picks a lit ball within 20 and the switch opens the door", "[bench][fastsim]") {
    const BitmapArena arena;
    BitmapCollectBall episode(arena, BitmapTask::source);
    episode.reset();
    episode.begin_start(0);
    float in[12] = {};
    const float grab[3] = {0.5f, 0.5f, 1.0f};

    // ball 0 at (296.25, 50.625): 19 away picks it, its light goes off
    episode.place({296.25f + 19, 50.625f, 0});
    REQUIRE(episode.apply(1, in, grab, {}));
    CHECK(episode.carrying());
    CHECK_FALSE(episode.lights()[0].on);
    episode.inputs(in);
    CHECK(in[11] == 1.0f);

    // the switch at (532.5, 40.5), 14.5 away: a carrying robot cannot press it
    episode.place({532.5f, 55, 0});
    REQUIRE(episode.apply(2, in, grab, {}));
    CHECK_FALSE(episode.door_open());
    episode.set_carrying(false);
    REQUIRE(episode.apply(3, in, grab, {}));
    CHECK(episode.door_open());
    CHECK_FALSE(episode.lights().back().on);

    // the next start closes the door and lights everything again
    episode.begin_start(1);
    CHECK_FALSE(episode.door_open());
    CHECK(episode.lights()[0].on);
    CHECK(episode.lights().back().on);
}

TEST_CASE("the target task's switch lights the ball and re-arms after 100 steps", "[bench][fastsim]") {
    const BitmapArena arena;
    BitmapCollectBall episode(arena, BitmapTask::target);
    episode.reset();
    episode.begin_start(0);
    // door open for the whole evaluation, the only ball (97.5, 50.625) off
    CHECK(episode.door_open());
    CHECK_FALSE(episode.lights()[0].on);
    float in[12] = {};
    const float grab[3] = {0.5f, 0.5f, 1.0f};
    episode.place({532.5f, 55, 0});
    episode.pre_step();
    REQUIRE(episode.apply(0, in, grab, {}));
    CHECK(episode.lights()[0].on);
    CHECK_FALSE(episode.lights().back().on);
    // the timer counts 100 steps down, then the switch is lit again
    for (int k = 0; k < 100; ++k) episode.pre_step();
    CHECK_FALSE(episode.lights().back().on);
    episode.pre_step();
    CHECK(episode.lights().back().on);
}

TEST_CASE("mis-sized recording buffers are refused", "[bench][fastsim]") {
    const BitmapArena arena;
    BitmapCollectBall episode(arena, BitmapTask::source);
    StillController controller;
    std::vector<float> behaviour(100);
    CHECK_THROWS_AS(run_bitmap_episode(episode, controller, {behaviour, {}}), std::invalid_argument);
}
