#include <catch2/catch.hpp>

#include <cmath>

#include "sim/arena.hpp"
#include "sim/robot.hpp"
#include "sim/units.hpp"

using namespace stepstone::sim;

namespace {

// a wall edge from the bitmap: pixel i covers [(i - 0.5) 600/296, (i + 0.5) 600/296)
double pixel_edge(double half_pixel) { return half_pixel * 600.0 / 296.0; }

}  // namespace

TEST_CASE("a laser facing the top wall reads the distance to its face", "[sim][arena]") {
    const Arena arena;
    // top wall = pixel rows 0-4, so its lower face is at 4.5 px = 9.1216 units
    const double face = pixel_edge(4.5);
    const double d = arena.ray_distance(300.0, 101.25, 0.0, -1.0, kLaserRange, false);
    CHECK(d == Approx(101.25 - face).margin(1e-3));
    // at 45 degrees the path to the same face is sqrt(2) longer
    const double r = std::sqrt(0.5);
    CHECK(arena.ray_distance(300.0, 101.25, r, -r, kLaserRange, false) ==
          Approx((101.25 - face) * std::sqrt(2.0)).margin(1e-3));
}

TEST_CASE("a laser with no wall within range reports nothing", "[sim][arena]") {
    const Arena arena;
    // from x = 230 the right wall's face (290.5 px = 588.85 units) is 358.85 away, beyond 320
    CHECK(arena.ray_distance(230.0, 101.25, 1.0, 0.0, kLaserRange, false) == -1.0);
    CHECK(arena.ray_distance(230.0, 101.25, 1.0, 0.0, 400.0, false) == Approx(pixel_edge(290.5) - 230.0));
}

TEST_CASE("a laser crosses the open door and stops at the closed one", "[sim][arena]") {
    const Arena arena;
    // y = 304 is inside the door rows 127-173 px; the divider's right face is 102.5 px = 207.77 units
    CHECK(arena.ray_distance(300.0, 304.0, -1.0, 0.0, kLaserRange, false) == Approx(300.0 - pixel_edge(102.5)));
    // open: the next wall west is the outer left wall, face at 4.5 px = 9.12 units
    CHECK(arena.ray_distance(300.0, 304.0, -1.0, 0.0, kLaserRange, true) == Approx(300.0 - pixel_edge(4.5)));
}

TEST_CASE("the robot disc collides within 20 units of a wall face", "[sim][arena]") {
    const Arena arena;
    const double face = pixel_edge(4.5);  // outer left wall's right face
    CHECK_FALSE(arena.disc_overlaps(face + 20.01, 150.0, false));
    CHECK(arena.disc_overlaps(face + 19.99, 150.0, false));
    // near the door: overlaps only while it is closed (divider's right face at 207.77)
    CHECK(arena.disc_overlaps(pixel_edge(102.5) + 19.0, 304.0, false));
    CHECK_FALSE(arena.disc_overlaps(pixel_edge(102.5) + 19.0, 304.0, true));
    // the start poses (docs/original.md: objects) are free
    CHECK_FALSE(arena.disc_overlaps(296.25, 101.25, false));
    CHECK_FALSE(arena.disc_overlaps(498.75, 303.75, false));
    CHECK_FALSE(arena.disc_overlaps(296.25, 303.75, false));
}

TEST_CASE("bumpers report the side of the contact relative to the heading", "[sim][arena]") {
    const Arena arena;
    const double top = pixel_edge(4.5);
    // wall above (bearing -pi/2 when heading east): the (-pi/2, 0) side, input 10
    const Contact up = arena.contact({300.0, top + 19.9, 0.0}, false);
    CHECK(up.hit);
    CHECK_FALSE(up.left);
    CHECK(up.right);
    // the same wall seen heading west lies at bearing +pi/2: the (0, pi/2) side, input 9
    const Contact up_west = arena.contact({300.0, top + 19.9, kPi}, false);
    CHECK(up_west.left);
    CHECK_FALSE(up_west.right);
    // head-on the overlap spans both sides of the heading (as fastsim's pixel scan)
    const Contact ahead = arena.contact({300.0, top + 18.0, -kPi / 2}, false);
    CHECK(ahead.left);
    CHECK(ahead.right);
    // behind: a collision with no bumper
    const Contact behind = arena.contact({300.0, top + 19.9, kPi / 2}, false);
    CHECK(behind.hit);
    CHECK_FALSE(behind.left);
    CHECK_FALSE(behind.right);
}

TEST_CASE("odometry follows the exact arc of a differential drive", "[sim][robot]") {
    // equal wheels: a straight line of 4 units along the heading
    const Pose straight = move_pose({100.0, 100.0, kPi / 2}, 4.0, 4.0);
    CHECK(straight.x == Approx(100.0).margin(1e-12));
    CHECK(straight.y == Approx(104.0));
    // opposite wheels: turn on the spot by (4 - (-4)) / 40 = 0.2 rad
    const Pose spin = move_pose({100.0, 100.0, 0.0}, -4.0, 4.0);
    CHECK(spin.x == Approx(100.0));
    CHECK(spin.y == Approx(100.0));
    CHECK(spin.heading == Approx(0.2));
    // left wheel still: pivot about it; the centre moves on a circle of radius 20
    // by 0.1 rad: (20 sin 0.1, 20 (1 - cos 0.1)) when heading east
    const Pose pivot = move_pose({100.0, 100.0, 0.0}, 0.0, 4.0);
    CHECK(pivot.x == Approx(100.0 + 20.0 * std::sin(0.1)));
    CHECK(pivot.y == Approx(100.0 + 20.0 * (1.0 - std::cos(0.1))));
    CHECK(pivot.heading == Approx(0.1));
    // headings wrap into (-pi, pi]
    CHECK(move_pose({0.0, 0.0, kPi - 0.05}, -4.0, 4.0).heading == Approx(-kPi + 0.15));
}
