#include <catch2/catch.hpp>
#include <cmath>

#include "core/rng.hpp"
#include "reference/box2d_world.hpp"
#include "sim/task.hpp"
#include "sim/units.hpp"

using namespace stepstone::sim;
using stepstone::reference::ReferenceWorld;

namespace {

bool inside_a_wall(const Arena& arena, double x, double y) {
    for (const WallBox& w : arena.walls()) {
        if (x >= w.x0 && x < w.x1 && y >= w.y0 && y < w.y1) return true;
    }
    return false;
}

}  // namespace

TEST_CASE("Box2D reference and fast geometry agree on lasers, lights and contacts at random poses",
          "[sim][reference][slow]") {
    const auto task = make_task(TaskConfig{});
    const Arena& arena = task->arena();
    const ReferenceWorld world(arena, task->lights());
    stepstone::Rng rng(20130101);  // fixed seed: a failure replays exactly

    constexpr int kPoses = 100'000;
    int laser_mismatch = 0;
    int light_mismatch = 0;
    int table_mismatch = 0;
    int contact_mismatch = 0;
    int bumper_mismatch = 0;
    int contacts = 0;
    double worst_laser = 0.0;
    for (int i = 0; i < kPoses; ++i) {
        // centres anywhere inside the outer walls but not inside a wall: the disc may overlap one
        Pose pose;
        do {
            pose = {rng.uniform(9.2, 588.8), rng.uniform(9.2, 394.2), rng.uniform(-kPi, kPi)};
        } while (inside_a_wall(arena, pose.x, pose.y));
        const WorldState state{rng.bernoulli(0.5), static_cast<std::uint32_t>(rng.below(1u << 13))};

        SensorReadings fast;
        SensorReadings reference;
        sense(arena, task->lights(), pose, state, fast);
        world.sense(pose, state, reference);
        for (std::size_t k = 0; k < 3; ++k) {
            const bool both_miss = fast.laser[k] < 0 && reference.laser[k] < 0;
            const double gap = std::fabs(fast.laser[k] - reference.laser[k]);
            if (!both_miss && (fast.laser[k] < 0) == (reference.laser[k] < 0)) worst_laser = std::max(worst_laser, gap);
            if (!both_miss && ((fast.laser[k] < 0) != (reference.laser[k] < 0) || gap > 0.01)) ++laser_mismatch;
        }
        if (fast.light != reference.light) ++light_mismatch;
        // the episode's path: sight lines restricted to precomputed candidate walls
        SensorReadings tabled;
        sense(arena, task->sight(), pose, state, tabled);
        if (tabled.light != fast.light || tabled.laser != fast.laser) ++table_mismatch;

        const Contact a = arena.contact(pose, state.door_open);
        const Contact b = world.contact(pose, state.door_open);
        contacts += a.hit ? 1 : 0;
        if (a.hit != b.hit) ++contact_mismatch;
        if (a.left != b.left || a.right != b.right) ++bumper_mismatch;
    }
    INFO("laser mismatches " << laser_mismatch << ", worst gap " << worst_laser << ", light mismatches "
                             << light_mismatch << ", contact mismatches " << contact_mismatch
                             << ", bumper mismatches " << bumper_mismatch << ", contacts " << contacts);
    // enough poses touch a wall for the contact comparison to mean something
    CHECK(contacts > kPoses / 20);
    CHECK(worst_laser <= 0.01);
    // at most 0.01 % of poses may differ (grazing rays and contacts)
    CHECK(laser_mismatch <= kPoses / 10'000);
    CHECK(light_mismatch <= kPoses / 10'000);
    CHECK(table_mismatch == 0);
    CHECK(contact_mismatch <= kPoses / 10'000);
    CHECK(bumper_mismatch <= kPoses / 10'000);
}

TEST_CASE("the reference world reads the door like the fast path", "[sim][reference]") {
    const auto task = make_task(TaskConfig{});
    const ReferenceWorld world(task->arena(), task->lights());
    // divider's right face at 102.5 px = 207.77 units, outer left face at 4.5 px = 9.12 units
    CHECK(world.ray_distance(300.0, 304.0, -1.0, 0.0, kLaserRange, false) ==
          Approx(300.0 - 102.5 * 600.0 / 296.0).margin(1e-3));
    CHECK(world.ray_distance(300.0, 304.0, -1.0, 0.0, kLaserRange, true) ==
          Approx(300.0 - 4.5 * 600.0 / 296.0).margin(1e-3));
    CHECK(world.contact({207.77 + 19.0, 304.0, 0.0}, false).hit);
    CHECK_FALSE(world.contact({207.77 + 19.0, 304.0, 0.0}, true).hit);
}
