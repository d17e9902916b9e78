#include "sim/episode.hpp"

#include <algorithm>
#include <bit>
#include <cstring>

#include "core/assert.hpp"
#include "core/error.hpp"
#include "core/text.hpp"
#include "sim/units.hpp"

namespace stepstone::sim {

namespace {

bool within(const Pose& pose, double x, double y, double radius) {
    const double dx = pose.x - x;
    const double dy = pose.y - y;
    return dx * dx + dy * dy <= radius * radius;
}

bool closer_than(const Pose& pose, const Light& light, double radius) {
    const double dx = pose.x - light.x;
    const double dy = pose.y - light.y;
    return dx * dx + dy * dy < radius * radius;
}

std::array<int, 2> cell_of(const Pose& pose) {
    return {static_cast<int>(pose.x * kGridTiles / kMapSize), static_cast<int>(pose.y * kGridTiles / kMapSize)};
}

}  // namespace

Episode::Episode(const Task& task, const Recording& recording) : task_(&task), recording_(recording) {
    if (!recording.behaviour.empty() && recording.behaviour.size() != task.behaviour_size()) {
        throw DataError(concat("behaviour buffer holds ", recording.behaviour.size(), " floats, the task needs ",
                               task.behaviour_size()));
    }
    if (!recording.cells.empty() && recording.cells.size() != task.cell_count()) {
        throw DataError(
            concat("cell buffer holds ", recording.cells.size(), " cells, the task needs ", task.cell_count()));
    }
    state_.door_open = task.door_starts_open();
    state_.lit = task.initial_lit();
    memos_.portable = task.config().math == Math::portable;
}

void Episode::begin_start(int index) {
    STEPSTONE_ASSERT(index >= 0 && index < task_->config().starts);
    const CosSinMemoScope scope(memos_);
    start_ = index;
    step_ = 0;

    // the original's move(0, 0) at the new pose senses before the reset below,
    // so the first inputs of starts 2 and 3 still see the previous start's
    // door and lights (docs/original.md: objects)
    pose_ = task_->start_pose(index);
    sense(task_->arena(), task_->sight(), pose_, state_, readings_);
    carrying_ = false;

    // reinit_simu: flags cleared, door and lights as at set-up, switch armed
    collided_ = false;
    bumper_left_ = bumper_right_ = false;
    state_.door_open = task_->door_starts_open();
    state_.lit = task_->initial_lit();
    switch_timer_ = 0;
}

void Episode::act(float* outputs, const float* inputs) {
    clamp_outputs(outputs);
    act_clamped(outputs, inputs);
}

void Episode::act_clamped(const float* outputs, const float* inputs) {
    const CosSinMemoScope scope(memos_);
    act_before_move(outputs, inputs);
    const Pose before = pose_;
    move(outputs[0], outputs[1]);
    end_step(before);
}

void Episode::act_before_move(const float* outputs, const float* inputs) {
    STEPSTONE_ASSERT(start_ >= 0 && !stopped_);
    record(inputs, outputs);
    apply_action(outputs[2]);
    milestones_.carry_steps += carrying_ ? 1 : 0;

    // the target task's switch re-arms when its timer has run out
    if (task_->spawn_ball_index() >= 0) {
        if (switch_timer_ == 0) {
            state_.lit |= 1u << task_->switch_index();
        } else {
            --switch_timer_;
        }
    }
}

void Episode::move_to(const Pose& next, const CosSin& heading, bool touches, std::uint32_t near) {
    STEPSTONE_ASSERT(start_ >= 0 && !stopped_);
    const CosSinMemoScope scope(memos_);
    // the bumpers and the sensors take the new heading's cos and sin from the memo
    memos_.heading.bits = std::bit_cast<std::uint64_t>(next.heading);
    memos_.heading.value = heading;
    const Pose before = pose_;
    take_move(next, touches ? task_->arena().contact_of_overlap(next, state_.door_open, near) : Contact{});
    still_rule(before);
    sense_lights(task_->arena(), task_->sight(), pose_, state_, readings_);
}

void Episode::still_rule(const Pose& before) {
    // the count is never reset and ends the whole evaluation
    if (is_still(before, pose_) && ++still_steps_ > task_->config().still_limit) stopped_ = true;
}

void Episode::end_step(const Pose& before) {
    still_rule(before);
    sense(task_->arena(), task_->sight(), pose_, state_, readings_);
    ++step_;
    ++steps_run_;
}

void Episode::record(const float* inputs, const float* outputs) {
    if (recording_.trace != nullptr) {
        recording_.trace->push_back(PoseSample{start_, step_, pose_.x, pose_.y, pose_.heading});
    }
    if (start_ != 0) return;
    if (!recording_.behaviour.empty()) {
        float* row = recording_.behaviour.data() + rows_written_ * kChannels;
        // memcpy of a size known when compiling, which GCC inlines (std::copy called memmove)
        if (inputs != nullptr) {
            std::memcpy(row, inputs, kInputs * sizeof(float));
        } else {
            read_inputs(row);
        }
        std::memcpy(row + kInputs, outputs, kOutputs * sizeof(float));
        ++rows_written_;
    }
    if (!recording_.cells.empty() && step_ % task_->config().grid_period == 0) {
        recording_.cells[cells_written_++] = cell_of(pose_);
    }
}

void Episode::apply_action(float action) {
    // release: scores only after a collision in this start and near the basket
    if (action < 0.5f) {
        if (carrying_) {
            carrying_ = false;
            const Basket& basket = task_->basket();
            if (within(pose_, basket.centre.x, basket.centre.y, basket.radius)) {
                ++milestones_.basket_releases;
                if (collided_) ++balls_;
            }
        }
        return;
    }
    if (carrying_) return;

    // grab: the first lit ball within reach, else the switch. The lights are visited in index
    // order, each lit one as the state stands when it is reached (a press lights the spawned
    // ball); basket lights cannot be grabbed and are skipped.
    const auto lights = task_->lights();
    const auto& kinds = task_->sight().kinds();
    const std::uint32_t grabbable =
        kinds[static_cast<std::size_t>(LightKind::ball)] | kinds[static_cast<std::size_t>(LightKind::switch_light)];
    if ((state_.lit & grabbable) == 0) return;
    // The reach test first, for the lit grabbable lights and the ball a press may light that
    // the sight table's cell puts near (on most steps none): the tests do not depend on one
    // another, so they overlap, and the visit below, in index order, sees only the lights
    // within reach.
    const int spawn = task_->spawn_ball_index();
    const std::uint32_t candidates = (state_.lit | (spawn >= 0 ? 1u << spawn : 0u)) & grabbable &
                                     task_->sight().reach_candidates(pose_.x, pose_.y);
    std::uint32_t reach = 0;
    for (std::uint32_t rest = candidates; rest != 0; rest &= rest - 1) {
        const auto i = static_cast<std::size_t>(std::countr_zero(rest));
        reach |= static_cast<std::uint32_t>(closer_than(pose_, lights[i], kReach)) << i;
    }
    std::uint32_t after = ~0u;  // the lights not visited yet
    for (std::uint32_t rest = state_.lit & reach; rest != 0; rest = state_.lit & reach & after) {
        const auto i = static_cast<std::size_t>(std::countr_zero(rest));
        const std::uint32_t bit = 1u << i;
        after = ~((bit << 1) - 1u);
        if (lights[i].kind == LightKind::ball) {
            carrying_ = true;
            state_.lit &= ~bit;
            ++milestones_.pickups;
            return;
        }
        if (lights[i].kind == LightKind::switch_light) {
            state_.lit &= ~bit;
            ++milestones_.presses;
            if (spawn >= 0) {
                state_.lit |= 1u << spawn;
                switch_timer_ = kSwitchRearmSteps;
            } else {
                state_.door_open = true;
            }
        }
    }
}

void Episode::move(float left_output, float right_output) {
    const Pose next = move_pose(pose_, wheel_step(left_output), wheel_step(right_output));
    take_move(next, task_->arena().contact(next, state_.door_open));
}

void Episode::take_move(const Pose& next, const Contact& contact) {
    // a blocked move keeps the position but takes the new heading
    if (contact.hit) {
        pose_.heading = next.heading;
        collided_ = true;
    } else {
        pose_ = next;
    }
    bumper_left_ = contact.left;
    bumper_right_ = contact.right;
}

void Episode::set_pose(const Pose& pose) {
    const CosSinMemoScope scope(memos_);
    pose_ = pose;
    sense(task_->arena(), task_->sight(), pose_, state_, readings_);
}

EpisodeResult Episode::finish() {
    // an early stop pads the first start's records: rows repeat the last row,
    // cells take the final position
    const std::size_t rows = static_cast<std::size_t>(task_->config().steps_per_start);
    if (!recording_.behaviour.empty() && rows_written_ == 0) {
        // no step recorded (none run): zeros, whatever the buffer held before
        std::fill(recording_.behaviour.begin(), recording_.behaviour.end(), 0.0f);
        rows_written_ = rows;
    }
    if (!recording_.behaviour.empty() && rows_written_ > 0) {
        const float* last = recording_.behaviour.data() + (rows_written_ - 1) * kChannels;
        for (std::size_t r = rows_written_; r < rows; ++r) {
            std::copy(last, last + kChannels, recording_.behaviour.data() + r * kChannels);
        }
        rows_written_ = rows;
    }
    for (; cells_written_ < recording_.cells.size(); ++cells_written_) {
        recording_.cells[cells_written_] = cell_of(pose_);
    }

    EpisodeResult result;
    result.balls = balls_;
    result.reward = static_cast<double>(balls_) / task_->reward_divisor();
    result.steps_run = steps_run_;
    result.stopped_early = stopped_;
    result.nan_outputs = nan_outputs_;
    result.milestones = milestones_;
    return result;
}

}  // namespace stepstone::sim
