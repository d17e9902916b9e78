// sim::run_episode_queue against run_episode, its oracle: every job of a queue,
// stepped in lanes with the others (portable runs: every lane's cos and sin at
// once, portable::sincos_lanes), gets the result, records and trace that its
// policy gets alone, for every lane count, queues longer than the lanes, early
// stops, NaN and saturated outputs, and both kinds of math.
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "sim/episode.hpp"
#include "sim/task.hpp"

using namespace stepstone;
using namespace stepstone::sim;

namespace {

// A policy with state: outputs mixed from the inputs and a generator of its own, restarted at
// each start. Kind by job: 0 turns and drives (arcs, walls, grabs and releases), 1 drives
// straight (equal wheels), 2 stops after a while (the stand-still rule ends it), 3 saturates
// and gives NaN now and then (clamped, replaced and counted).
struct Policy {
    std::uint64_t seed = 0;
    int kind = 0;
    std::uint64_t state = 0;
    int steps = 0;

    void reset() {
        state = seed * 0x9e3779b97f4a7c15ull + 1;
        steps = 0;
    }
    float noise() {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return static_cast<float>(state >> 40) * 0x1.0p-24f;
    }
    void step(const float* in, float* out) {
        ++steps;
        const float n = noise();
        out[0] = 0.5f + 0.6f * (in[0] - in[2]) + 0.4f * (n - 0.3f);
        out[1] = 0.5f + 0.6f * (in[1] - in[2]) + 0.3f * (noise() - 0.2f) + 0.2f * in[9];
        out[2] = in[3] + in[4] + in[11] > 0.5f || n > 0.8f ? 1.0f : 0.0f;
        if (kind == 1) out[1] = out[0];
        if (kind == 2 && steps > 60 + static_cast<int>(seed % 50)) out[0] = out[1] = 0.5f;
        if (kind == 3) {
            out[0] = 3.0f * out[0] - 1.0f;
            if (n < 0.05f) out[1] = std::numeric_limits<float>::quiet_NaN();
        }
    }
};

Policy policy_of(std::size_t job) { return Policy{job * 7 + 3, static_cast<int>(job % 4)}; }

// the lanes controller: one Policy a lane, loaded by job
struct PolicyLanes {
    std::size_t lane_count = 1;
    std::vector<Policy> policies = std::vector<Policy>(32);
    std::vector<std::array<float, kInputs>> inputs = std::vector<std::array<float, kInputs>>(32);
    std::vector<std::array<float, kOutputs>> outputs = std::vector<std::array<float, kOutputs>>(32);

    std::size_t lanes() const { return lane_count; }
    void load(std::size_t lane, std::size_t job) {
        policies[lane] = policy_of(job);
        policies[lane].reset();
    }
    void reset(std::size_t lane) { policies[lane].reset(); }
    void set_inputs(std::size_t lane, const float* in) { std::copy(in, in + kInputs, inputs[lane].begin()); }
    void step() {
        for (std::size_t l = 0; l < lane_count; ++l) policies[l].step(inputs[l].data(), outputs[l].data());
    }
    void get_outputs(std::size_t lane, float* out) const {
        std::copy(outputs[lane].begin(), outputs[lane].end(), out);
    }
};

struct Records {
    EpisodeResult result;
    std::vector<float> behaviour;
    std::vector<std::array<int, 2>> cells;
    std::vector<PoseSample> trace;
};

void require_same(const Records& lanes, const Records& alone) {
    CHECK(lanes.result.reward == alone.result.reward);
    CHECK(lanes.result.balls == alone.result.balls);
    CHECK(lanes.result.steps_run == alone.result.steps_run);
    CHECK(lanes.result.stopped_early == alone.result.stopped_early);
    CHECK(lanes.result.nan_outputs == alone.result.nan_outputs);
    CHECK(lanes.result.milestones == alone.result.milestones);
    CHECK(lanes.behaviour == alone.behaviour);
    CHECK(lanes.cells == alone.cells);
    REQUIRE(lanes.trace.size() == alone.trace.size());
    std::size_t differences = 0;
    for (std::size_t i = 0; i < lanes.trace.size(); ++i) {
        const PoseSample& a = lanes.trace[i];
        const PoseSample& b = alone.trace[i];
        // exact comparison: the same doubles, not close ones
        differences +=
            a.start != b.start || a.step != b.step || a.x != b.x || a.y != b.y || a.heading != b.heading;
    }
    CHECK(differences == 0);
}

void check_queues_match_alone(Math math, TaskKind kind = TaskKind::source) {
    TaskConfig config;
    config.kind = kind;
    config.steps_per_start = 400;
    config.still_limit = 40;
    config.math = math;
    const auto task = make_task(config);
    const auto recording_of = [&](Records& records) {
        records.behaviour.assign(task->behaviour_size(), -1.0f);
        records.cells.assign(task->cell_count(), {-1, -1});
        records.trace.reserve(3 * 400);
        return Recording{records.behaviour, records.cells, &records.trace};
    };
    std::vector<Records> alone(19);
    long arcs_and_stops = 0;
    for (std::size_t job = 0; job < alone.size(); ++job) {
        Policy policy = policy_of(job);
        alone[job].result = run_episode(*task, policy, recording_of(alone[job]));
        arcs_and_stops += alone[job].result.stopped_early ? 1 : 0;
    }
    REQUIRE(arcs_and_stops >= 4);  // early stops among the jobs, so lanes take new jobs mid-queue
    REQUIRE(alone[3].result.nan_outputs > 0);
    REQUIRE(alone[0].behaviour != alone[4].behaviour);

    for (std::size_t lanes = 1; lanes <= 8; ++lanes) {
        // queues shorter than, as long as and longer than the lanes
        for (const std::size_t jobs : {std::max<std::size_t>(1, lanes - 1), lanes, 2 * lanes + 3}) {
            if (jobs > alone.size()) continue;
            INFO(lanes << " lanes, " << jobs << " jobs, math " << to_string(math) << ", task "
                       << to_string(kind));
            PolicyLanes controller;
            controller.lane_count = lanes;
            std::vector<Records> records(jobs);
            std::vector<int> done(jobs, 0);
            run_episode_queue(
                *task, controller, jobs, [&](std::size_t job) { return recording_of(records[job]); },
                [&](std::size_t job, const EpisodeResult& result) {
                    records[job].result = result;
                    ++done[job];
                });
            for (std::size_t job = 0; job < jobs; ++job) {
                INFO("job " << job);
                REQUIRE(done[job] == 1);
                require_same(records[job], alone[job]);
            }
        }
    }
}

}  // namespace

TEST_CASE("queues of episodes in lanes equal each episode alone, portable math", "[sim][episode][lanes]") {
    check_queues_match_alone(Math::portable);
}

TEST_CASE("queues of episodes in lanes equal each episode alone, target task (door open)",
          "[sim][episode][lanes]") {
    check_queues_match_alone(Math::portable, TaskKind::target);
}

TEST_CASE("queues of episodes in lanes equal each episode alone, libm math", "[sim][episode][lanes]") {
    check_queues_match_alone(Math::libm);
}
