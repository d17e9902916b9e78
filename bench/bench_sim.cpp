// `sim`: the sensor + motion step of lib/sim against the bitmap baseline.

#include <memory>

#include "bench/cases.hpp"
#include "bench/drive_plan.hpp"
#include "reference/fastsim_baseline.hpp"
#include "sim/arena.hpp"
#include "sim/robot.hpp"
#include "sim/sensors.hpp"
#include "sim/task.hpp"

namespace stepstone::bench {

using namespace stepstone::reference;  // the baselines

namespace {

// steps per call, each call the same drive (80 placements); --quick keeps
// the same drive, so its rates are comparable, and only times fewer rounds
constexpr int kSteps = 4000;

// the candidate's step as sim::Episode composes it: odometry, contact at the
// attempted pose, sensing at the final pose (with the task's precomputed
// sight lines), the 12 inputs
struct CandidateRobot {
    std::shared_ptr<const sim::Task> task;
    sim::WorldState state;
    sim::SensorReadings readings;
    float inputs[sim::kInputs] = {};
    float checksum = 0;

    std::uint64_t run(const DrivePlan& plan) {
        sim::Pose pose;
        for (std::size_t k = 0; k < plan.commands.size(); ++k) {
            if (k % static_cast<std::size_t>(plan.segment) == 0) {
                const auto& start = plan.starts[k / static_cast<std::size_t>(plan.segment)];
                pose = {start[0], start[1], start[2]};
            }
            const auto& command = plan.commands[k];
            const sim::Pose next =
                sim::move_pose(pose, sim::wheel_step(command[0]), sim::wheel_step(command[1]));
            const sim::Contact contact = task->arena().contact(next, state.door_open);
            if (contact.hit) {
                pose.heading = next.heading;
            } else {
                pose = next;
            }
            sim::sense(task->arena(), task->sight(), pose, state, readings);
            sim::fill_inputs(readings, contact.left, contact.right, false, inputs);
            checksum += inputs[2];
        }
        return plan.commands.size();
    }
};

// the baseline's step: BitmapRobot::move does odometry, pixel collision and
// every sensor
struct BaselineRobot {
    std::shared_ptr<const BitmapArena> arena = std::make_shared<BitmapArena>();
    std::vector<Light> lights;
    BitmapRobot robot;
    float inputs[11] = {};
    float checksum = 0;

    std::uint64_t run(const DrivePlan& plan) {
        for (std::size_t k = 0; k < plan.commands.size(); ++k) {
            if (k % static_cast<std::size_t>(plan.segment) == 0) {
                const auto& start = plan.starts[k / static_cast<std::size_t>(plan.segment)];
                robot.set_pose({start[0], start[1], start[2]});
            }
            const auto& command = plan.commands[k];
            robot.move(4 * (2 * command[0] - 1), 4 * (2 * command[1] - 1), arena->closed, lights);
            robot.sensor_inputs(inputs);
            checksum += inputs[2];
        }
        return plan.commands.size();
    }
};

Workload make_sim_workload(Size) {
    auto plan = std::make_shared<const DrivePlan>(drive_plan(kSteps, 11));

    // the source task at its first step: 13 lights, all lit, door closed
    auto candidate = std::make_shared<CandidateRobot>();
    candidate->task = sim::make_task(sim::TaskConfig{});
    candidate->state.door_open = false;
    candidate->state.lit = candidate->task->initial_lit();

    // the baseline's own definition of the same scene
    auto baseline = std::make_shared<BaselineRobot>();
    const BitmapCollectBall source(*baseline->arena, BitmapTask::source);
    baseline->lights.assign(source.lights().begin(), source.lights().end());

    return Workload{[baseline, plan] { return baseline->run(*plan); },
                    [candidate, plan] { return candidate->run(*plan); }};
}

}  // namespace

void add_sim_cases(Registry& registry) {
    registry.add(Case{"sim", "steps",
                      "sensor + motion step on a fixed drive over the arena: lib/sim vs the 296x296 bitmap",
                      20.0, make_sim_workload});
}

}  // namespace stepstone::bench
