#include "sim/episode.hpp"

#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "core/error.hpp"
#include "scripted_steps.hpp"
#include "sim/controllers.hpp"
#include "sim/task.hpp"
#include "sim/units.hpp"

using namespace stepstone::sim;
using Catch::Matchers::Contains;

namespace {

// wall faces from the bitmap: pixel i covers [(i - 0.5) 600/296, (i + 0.5) 600/296)
constexpr double kTopFace = 4.5 * 600.0 / 296.0;       // 9.1216
using stepstone::simtest::act;
using stepstone::simtest::kBottomFace;

std::array<float, kInputs> inputs_of(const Episode& episode) {
    std::array<float, kInputs> inputs{};
    episode.read_inputs(inputs.data());
    return inputs;
}

// drives full speed for `moving` steps, then outputs (0.5, 0.5, 0): both wheels still
struct DriveThenStop {
    int moving = 0;
    int step_count = 0;
    void reset() {}
    void step(const float*, float* outputs) {
        const float wheel = step_count++ < moving ? 1.0f : 0.5f;
        outputs[0] = outputs[1] = wheel;
        outputs[2] = 0.0f;
    }
};

}  // namespace

TEST_CASE("a collision keeps the position, turns the heading, sets the flag and the right bumper",
          "[sim][episode][collision]") {
    const auto task = make_task(TaskConfig{});
    Episode episode(*task);
    episode.begin_start(0);
    // heading east 20.08 units below the top wall's face; left wheel 4, right 0
    // turns by -0.1 rad and lifts the centre by 20 (1 - cos 0.1) = 0.0999: 19.98 from the wall
    episode.set_pose({300.0, kTopFace + 20.08, 0.0});
    CHECK_FALSE(episode.collided());
    act(episode, 1.0f, 0.5f, 0.0f);
    CHECK(episode.pose().x == 300.0);
    CHECK(episode.pose().y == kTopFace + 20.08);
    CHECK(episode.pose().heading == Approx(-0.1));
    CHECK(episode.collided());
    // the wall is at bearing -pi/2 + 0.1: the (-pi/2, 0) side, input 10
    const auto inputs = inputs_of(episode);
    CHECK(inputs[9] == 0.0f);
    CHECK(inputs[10] == 1.0f);

    // moving away clears the bumpers, not the sticky collision flag
    act(episode, 0.0f, 0.0f, 0.0f);
    CHECK(inputs_of(episode)[10] == 0.0f);
    CHECK(episode.collided());
    // a new start clears it
    episode.begin_start(1);
    CHECK_FALSE(episode.collided());
}

TEST_CASE("the mirrored contact against the bottom wall sets the left bumper", "[sim][episode][collision]") {
    const auto task = make_task(TaskConfig{});
    Episode episode(*task);
    episode.begin_start(0);
    // heading east 20.06 above the bottom face; right wheel 4 turns by +0.1 and lowers the centre by 0.0999
    episode.set_pose({300.0, kBottomFace - 20.06, 0.0});
    act(episode, 0.5f, 1.0f, 0.0f);
    CHECK(episode.pose().y == kBottomFace - 20.06);
    CHECK(episode.pose().heading == Approx(0.1));
    const auto inputs = inputs_of(episode);
    CHECK(inputs[9] == 1.0f);
    CHECK(inputs[10] == 0.0f);
}

TEST_CASE("driving at full speed into walls never tunnels through them", "[sim][episode][collision]") {
    // pushing against a wall is standing still: lift the stand-still limit
    TaskConfig config;
    config.still_limit = 1'000'000;
    const auto task = make_task(config);
    Episode episode(*task);
    episode.begin_start(0);
    // into the closed door from the east: the centre stops within one step (4 units) of 207.77 + 20
    const double divider_face = 102.5 * 600.0 / 296.0;
    episode.set_pose({300.0, 304.0, kPi});
    for (int i = 0; i < 40; ++i) act(episode, 1.0f, 1.0f, 0.0f);
    CHECK(episode.pose().x >= divider_face + 20.0);
    CHECK(episode.pose().x < divider_face + 24.0);
    // many headings from the middle of the upper room: the disc never overlaps a wall
    for (int k = 0; k < 64; ++k) {
        Episode e(*task);
        e.begin_start(0);
        e.set_pose({300.0, 100.0, -kPi + k * kPi / 32});
        for (int i = 0; i < 150; ++i) act(e, 1.0f, 1.0f, 0.0f);
        REQUIRE_FALSE(task->arena().disc_overlaps(e.pose().x, e.pose().y, false));
    }
}

TEST_CASE("a release pressed against the bottom wall under the lights scores", "[sim][episode][scoring]") {
    const auto task = make_task(TaskConfig{});
    Episode episode(*task);
    episode.begin_start(0);
    // facing down, 20.06 above the bottom face at the basket's x: a full-speed step collides
    episode.set_pose({paper_arena().basket.centre.x, kBottomFace - 20.06, kPi / 2});
    episode.set_carrying(true);
    act(episode, 1.0f, 1.0f, 1.0f);
    REQUIRE(episode.collided());
    // the centre is 405 - 374.20 = 30.80 from the basket centre, within 33.75
    act(episode, 0.0f, 0.0f, 0.0f);
    CHECK(episode.balls() == 1);
    CHECK_FALSE(episode.carrying());
    CHECK(episode.finish().reward == Approx(1.0 / 24.0));
}

TEST_CASE("a release away from the basket loses the ball", "[sim][episode][scoring]") {
    const auto task = make_task(TaskConfig{});
    Episode episode(*task);
    episode.begin_start(0);
    // against the bottom wall at x = 250: sqrt(46.25^2 + 30.8^2) = 55.6 from the basket centre
    episode.set_pose({250.0, kBottomFace - 20.06, kPi / 2});
    episode.set_carrying(true);
    act(episode, 1.0f, 1.0f, 1.0f);
    REQUIRE(episode.collided());
    act(episode, 0.0f, 0.0f, 0.0f);
    CHECK(episode.balls() == 0);
    CHECK_FALSE(episode.carrying());
}

TEST_CASE("a release near the basket without a prior collision does not score", "[sim][episode][scoring]") {
    const auto task = make_task(TaskConfig{});
    Episode episode(*task);
    episode.begin_start(0);
    // 30.80 from the basket centre but no wall touched in this start
    episode.set_pose({paper_arena().basket.centre.x, kBottomFace - 20.06, 0.0});
    episode.set_carrying(true);
    act(episode, 0.5f, 0.5f, 0.0f);
    CHECK(episode.balls() == 0);
    CHECK_FALSE(episode.carrying());
}

TEST_CASE("a grab picks a lit ball within 20 units and switches its light off", "[sim][episode]") {
    const auto task = make_task(TaskConfig{});
    Episode episode(*task);
    episode.begin_start(0);
    // ball 0 at (296.25, 50.625); 20.5 away: out of reach
    episode.set_pose({296.25, 71.125, 0.0});
    act(episode, 0.0f, 1.0f, 1.0f);
    CHECK_FALSE(episode.carrying());
    // exactly 20 away (20^2 = 400 with no rounding): reach is strictly closer than 20
    episode.set_pose({296.25, 70.625, 0.0});
    act(episode, 0.0f, 1.0f, 1.0f);
    CHECK_FALSE(episode.carrying());
    episode.set_pose({296.25, 69.625, 0.0});  // 19 away
    act(episode, 0.0f, 1.0f, 1.0f);
    CHECK(episode.carrying());
    CHECK((episode.lit() & 1u) == 0);
    CHECK(inputs_of(episode)[11] == 1.0f);
}

TEST_CASE("the source switch opens the door until the next start", "[sim][episode][tasks]") {
    const auto task = make_task(TaskConfig{});
    Episode episode(*task);
    episode.begin_start(0);
    CHECK_FALSE(episode.door_open());
    episode.set_pose({532.5, 55.0, 0.0});  // 14.5 from the switch at (532.5, 40.5)
    act(episode, 0.0f, 1.0f, 1.0f);
    CHECK(episode.door_open());
    CHECK((episode.lit() >> task->switch_index() & 1u) == 0);
    episode.begin_start(1);
    CHECK_FALSE(episode.door_open());
    CHECK(episode.lit() == task->initial_lit());
}

TEST_CASE("the target switch spawns the ball at (97.5, 50.625) and re-arms after 100 steps",
          "[sim][episode][tasks]") {
    const auto task = make_task(TaskConfig{TaskKind::target});
    const auto ball = task->lights()[static_cast<std::size_t>(task->spawn_ball_index())];
    CHECK(ball.x == 97.5);  // 195 / 2
    CHECK(ball.y == 50.625);  // 405 / 8
    const std::uint32_t ball_bit = 1u << task->spawn_ball_index();
    const std::uint32_t switch_bit = 1u << task->switch_index();

    Episode episode(*task);
    episode.begin_start(0);
    CHECK(episode.door_open());
    CHECK((episode.lit() & ball_bit) == 0);
    episode.set_pose({532.5, 55.0, 0.0});
    act(episode, 0.0f, 1.0f, 1.0f);  // press, while turning on the spot
    CHECK((episode.lit() & ball_bit) != 0);
    CHECK((episode.lit() & switch_bit) == 0);
    // off during the press step and the 99 after it, lit again by the 100th
    for (int i = 1; i < kSwitchRearmSteps; ++i) {
        act(episode, 0.0f, 1.0f, 0.0f);
        REQUIRE((episode.lit() & switch_bit) == 0);
    }
    act(episode, 0.0f, 1.0f, 0.0f);
    CHECK((episode.lit() & switch_bit) != 0);
}

TEST_CASE("a still controller stops the evaluation after 101 still steps", "[sim][episode][still]") {
    const auto task = make_task(TaskConfig{});
    std::vector<float> behaviour(task->behaviour_size());
    std::vector<std::array<int, 2>> cells(task->cell_count());
    ConstantController still(0.5f, 0.5f, 0.0f);
    const auto result = run_episode(*task, still, Recording{behaviour, cells});
    // more than 100 still steps: the 101st ends the whole evaluation
    CHECK(result.steps_run == 101);
    CHECK(result.stopped_early);
    CHECK(result.reward == 0.0);
    // start 1 at (296.25, 101.25): cell (5.925 -> 5, 2.025 -> 2)
    for (const auto& cell : cells) CHECK(cell == std::array<int, 2>{5, 2});
}

TEST_CASE("an early stop pads the trajectory with the final cell and repeats the last row",
          "[sim][episode][still]") {
    const auto task = make_task(TaskConfig{});
    std::vector<float> behaviour(task->behaviour_size(), -1.0f);
    std::vector<std::array<int, 2>> cells(task->cell_count(), {-1, -1});
    // 15 steps of 4 units at +pi/4 from (296.25, 101.25): (338.68, 143.68), cell (6, 2)
    DriveThenStop controller{15};
    const auto result = run_episode(*task, controller, Recording{behaviour, cells});
    CHECK(result.steps_run == 15 + 101);
    CHECK(cells.size() == 80);
    CHECK(cells[0] == std::array<int, 2>{5, 2});  // step 0, the start pose
    CHECK(cells[1] == std::array<int, 2>{6, 2});  // step 50, already still
    CHECK(cells[2] == std::array<int, 2>{6, 2});  // step 100
    for (std::size_t i = 3; i < cells.size(); ++i) CHECK(cells[i] == std::array<int, 2>{6, 2});
    // rows after the stop repeat row 115; the outputs there are (0.5, 0.5, 0)
    const float* last = behaviour.data() + 115 * kChannels;
    CHECK(last[kInputs] == 0.5f);
    for (std::size_t r = 116; r < 4000; ++r) {
        REQUIRE(std::equal(last, last + kChannels, behaviour.data() + r * kChannels));
    }
}

TEST_CASE("an episode finished before its first step leaves zeros, not what the buffer held",
          "[sim][episode][still]") {
    // evaluations write into buffers kept from one generation to the next: every slot is theirs
    const auto task = make_task(TaskConfig{});
    std::vector<float> behaviour(task->behaviour_size(), -1.0f);
    Episode episode(*task, Recording{behaviour, {}});
    episode.begin_start(0);
    const auto result = episode.finish();
    CHECK(result.steps_run == 0);
    CHECK(std::count(behaviour.begin(), behaviour.end(), 0.0f) == static_cast<long>(behaviour.size()));
}

TEST_CASE("NaN outputs become 0 and are counted, others are clamped", "[sim][episode]") {
    struct Wild {
        void reset() {}
        void step(const float*, float* outputs) {
            outputs[0] = std::nanf("");
            outputs[1] = 7.0f;
            outputs[2] = -3.0f;
        }
    } wild;
    TaskConfig config;
    config.steps_per_start = 20;
    config.starts = 1;
    const auto task = make_task(config);
    std::vector<float> behaviour(task->behaviour_size());
    const auto result = run_episode(*task, wild, Recording{behaviour, {}});
    CHECK(result.nan_outputs == 20);
    CHECK(behaviour[kInputs] == 0.0f);
    CHECK(behaviour[kInputs + 1] == 1.0f);
    CHECK(behaviour[kInputs + 2] == 0.0f);
}

TEST_CASE("mis-sized recording buffers and bad configs are refused with a message", "[sim][episode][errors]") {
    const auto task = make_task(TaskConfig{});
    std::vector<float> wrong(10);
    ConstantController still(0.5f, 0.5f, 0.0f);
    CHECK_THROWS_AS(run_episode(*task, still, Recording{wrong, {}}), stepstone::DataError);
    CHECK_THROWS_WITH(run_episode(*task, still, Recording{wrong, {}}), Contains("behaviour buffer holds 10"));
    TaskConfig config;
    config.starts = 4;
    CHECK_THROWS_AS(make_task(config), stepstone::ConfigError);
    CHECK_THROWS_WITH(make_task(config), Contains("starts must be in [1, 3], got 4"));
    config = TaskConfig{};
    config.steps_per_start = 0;
    CHECK_THROWS_WITH(make_task(config), Contains("steps_per_start"));
    CHECK_THROWS_WITH(parse_task_kind("middle", "--task"), Contains("--task must be source or target"));
}
