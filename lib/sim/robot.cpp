#include "sim/robot.hpp"

#include <cmath>

#include "sim/cos_sin.hpp"
#include "sim/units.hpp"

namespace stepstone::sim {

double normalize_angle(double angle) {
    // headings change by at most 0.2 rad per step, so one wrap is the common case
    while (angle > kPi) angle -= 2.0 * kPi;
    while (angle <= -kPi) angle += 2.0 * kPi;
    return angle;
}

namespace {

// a move's angles, one expression each for move_pose() and move_angles()
double turn_of(double left, double right) { return (right - left) / kWheelBase; }
bool is_straight(double alpha) { return std::fabs(alpha) <= 1e-10; }
double rotation_of(const Pose& pose) { return pose.heading - kPi / 2.0; }
double heading_after(const Pose& pose, double alpha) { return normalize_angle(pose.heading + alpha); }

// the arc of a turning move, with the run's sin and cos known at compile time (one branch a move);
// the portable one reads the rotation memo, which the lanes of run_episode_queue fill ahead
template <bool Portable>
Pose move_arc(const Pose& pose, double left, double alpha, CosSinMemos& memos) {
    Pose next = pose;
    // an arc about the instantaneous centre, computed in the robot frame
    // (forward = local +y) and rotated by heading - pi/2 into the world
    const double radius = left / alpha + kWheelBase / 2.0;
    const CosSin turn = memos.turn.get(alpha, Portable);
    const double local_x = (turn.c - 1.0) * radius;
    const double local_y = turn.s * radius;
    CosSin rotation;
    if constexpr (Portable) {
        rotation = memos.rotation.get(rotation_of(pose), true);
    } else {
        rotation = CosSinMemo::compute<false>(rotation_of(pose));
    }
    const double c = rotation.c;
    const double s = rotation.s;
    next.x += local_x * c - local_y * s;
    next.y += local_x * s + local_y * c;
    next.heading = heading_after(pose, alpha);
    return next;
}

}  // namespace

Pose move_pose(const Pose& pose, double left, double right) {
    const double alpha = turn_of(left, right);

    // nearly equal wheels: a straight line of the left wheel's length
    if (is_straight(alpha)) {
        Pose next = pose;
        const CosSin heading = cos_sin(pose.heading);
        next.x += left * heading.c;
        next.y += left * heading.s;
        return next;
    }
    CosSinMemos& memos = current_memos();
    return memos.portable ? move_arc<true>(pose, left, alpha, memos)
                          : move_arc<false>(pose, left, alpha, memos);
}

MoveAngles move_angles(const Pose& pose, double left, double right) {
    const double alpha = turn_of(left, right);
    if (is_straight(alpha)) return {false, 0.0, 0.0, pose.heading};
    return {true, alpha, rotation_of(pose), heading_after(pose, alpha)};
}

bool is_still(const Pose& before, const Pose& after) {
    const double dx = after.x - before.x;
    const double dy = after.y - before.y;
    const double turn = std::fabs(normalize_angle(after.heading - before.heading));
    return dx * dx + dy * dy < kStillEpsilon * kStillEpsilon && turn < kStillEpsilon;
}

}  // namespace stepstone::sim
