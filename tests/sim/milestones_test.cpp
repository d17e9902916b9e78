// Milestones (docs/simulator.md: milestones) on scripted step sequences whose
// counts are worked out by hand from the task rules, and on the scripted
// controller's full evaluations, whose counts follow from the rules too.

#include <array>
#include <catch2/catch.hpp>

#include "scripted_steps.hpp"
#include "sim/controllers.hpp"
#include "sim/episode.hpp"
#include "sim/task.hpp"
#include "sim/units.hpp"

using namespace stepstone::sim;

namespace {

using stepstone::simtest::act;
using stepstone::simtest::kBottomFace;

// still wheels (0.5, 0.5) with the action output held at `action`, `steps` times
void hold(Episode& episode, float action, int steps) {
    for (int i = 0; i < steps; ++i) act(episode, 0.5f, 0.5f, action);
}

// against the bottom wall under the basket: a full-speed step down collides
// (sets the sticky flag) and leaves the centre 30.80 from the basket centre
void collide_at_basket(Episode& episode, float action) {
    episode.set_pose({paper_arena().basket.centre.x, kBottomFace - 20.06, kPi / 2});
    act(episode, 1.0f, 1.0f, action);
}

}  // namespace

TEST_CASE("source task: presses, pickups, carried steps and basket releases counted by hand",
          "[sim][milestones]") {
    const auto task = make_task(TaskConfig{});
    Episode episode(*task);
    episode.begin_start(0);

    // 14.5 from the switch: the first grab presses it, the second finds it off (source: off until the next
    // start)
    episode.set_pose({532.5, 55.0, 0.0});
    act(episode, 0.0f, 1.0f, 1.0f);
    act(episode, 0.0f, 1.0f, 1.0f);
    CHECK(episode.milestones().presses == 1);

    // ball 1 at (296.25, 151.875), 19 away: picked up; 1 grab step + 9 held steps end carrying
    episode.set_pose({296.25, 170.875, 0.0});
    hold(episode, 1.0f, 10);
    CHECK(episode.milestones().pickups == 1);
    CHECK(episode.milestones().carry_steps == 10);
    // released in the open: lost, not a basket release, and the release step is not a carrying step
    hold(episode, 0.0f, 1);
    CHECK(episode.milestones().basket_releases == 0);
    CHECK(episode.milestones().carry_steps == 10);

    // ball 2 at (397.5, 50.625): released within the basket radius before any collision
    // in this start: a basket release that does not score
    episode.set_pose({397.5, 69.625, 0.0});
    hold(episode, 1.0f, 3);  // carry steps 11, 12, 13
    episode.set_pose({paper_arena().basket.centre.x, kBottomFace - 20.06, 0.0});
    hold(episode, 0.0f, 1);
    CHECK(episode.milestones().basket_releases == 1);
    CHECK(episode.balls() == 0);

    // ball 3 at (397.5, 151.875): carried into the bottom wall (a collision), released: scores
    episode.set_pose({397.5, 170.875, 0.0});
    hold(episode, 1.0f, 2);            // carry steps 14, 15
    collide_at_basket(episode, 1.0f);  // carry step 16
    hold(episode, 0.0f, 1);
    CHECK(episode.balls() == 1);

    // a second start: the switch is lit again and is pressed once more
    episode.begin_start(1);
    episode.set_pose({532.5, 55.0, 0.0});
    act(episode, 0.0f, 1.0f, 1.0f);

    const EpisodeResult result = episode.finish();
    CHECK(result.milestones ==
          Milestones{.presses = 2, .pickups = 3, .carry_steps = 16, .basket_releases = 2});
    CHECK(result.balls == 1);
}

TEST_CASE("target task: a press every 101 steps at most, the spawned ball carried and scored",
          "[sim][milestones]") {
    const auto task = make_task(TaskConfig{TaskKind::target});
    Episode episode(*task);
    episode.begin_start(0);

    // 102 grabs at the switch: pressed at step 0, off until the tick of step 100, pressed again at step 101
    episode.set_pose({532.5, 55.0, 0.0});
    for (int i = 0; i < 101; ++i) act(episode, 0.0f, 1.0f, 1.0f);
    CHECK(episode.milestones().presses == 1);
    act(episode, 0.0f, 1.0f, 1.0f);
    CHECK(episode.milestones().presses == 2);

    // the spawned ball at (97.5, 50.625), 19 away: 1 grab step + 4 held steps, then into the wall (step 6)
    episode.set_pose({97.5, 69.625, 0.0});
    hold(episode, 1.0f, 5);
    collide_at_basket(episode, 1.0f);
    hold(episode, 0.0f, 1);
    CHECK(episode.balls() == 1);

    // the ball is off once taken: a grab where it was picks nothing up
    episode.set_pose({97.5, 69.625, 0.0});
    hold(episode, 1.0f, 1);

    const EpisodeResult result = episode.finish();
    CHECK(result.milestones ==
          Milestones{.presses = 2, .pickups = 1, .carry_steps = 6, .basket_releases = 1});
}

TEST_CASE("the scripted controller's milestones follow from the task rules", "[sim][milestones]") {
    SECTION("source: one press a start, and every ball taken is scored") {
        // 24 balls scored, each taken once (its light goes off) from the 8 lit per start, so
        // pickups = basket releases = 24; the left-room balls need the door, pressed once a start
        const auto task = make_task(TaskConfig{});
        ScriptedController controller(TaskKind::source);
        const EpisodeResult result = run_episode(*task, controller);
        REQUIRE(result.balls == 24);
        CHECK(result.milestones.presses == 3);
        CHECK(result.milestones.pickups == 24);
        CHECK(result.milestones.basket_releases == 24);
        CHECK(result.milestones.carry_steps > 0);
    }
    SECTION("target: every pickup needs a press, every ball scored a pickup") {
        const auto task = make_task(TaskConfig{TaskKind::target});
        ScriptedController controller(TaskKind::target);
        const EpisodeResult result = run_episode(*task, controller);
        REQUIRE(result.balls == 18);
        CHECK(result.milestones.pickups >= result.milestones.basket_releases);
        CHECK(result.milestones.presses >= result.milestones.pickups);
        CHECK(result.milestones.basket_releases >= 18);
    }
}

TEST_CASE("a controller that never grabs reaches no milestone", "[sim][milestones]") {
    // the action output stays below 0.5: no grab, so no press, pickup, carry or release
    const auto task = make_task(TaskConfig{TaskKind::target});
    ConstantController wander(1.0f, 0.9f, 0.0f);
    const EpisodeResult result = run_episode(*task, wander);
    CHECK(result.steps_run > 0);
    CHECK(result.milestones == Milestones{});
}
