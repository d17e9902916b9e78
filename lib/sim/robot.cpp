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

// the arc of a turning move, with the run's sin and cos known at compile time (one branch a move)
template <bool Portable>
Pose move_arc(const Pose& pose, double left, double alpha, CosSinMemo& turn_memo) {
    Pose next = pose;
    // an arc about the instantaneous centre, computed in the robot frame
    // (forward = local +y) and rotated by heading - pi/2 into the world
    const double radius = left / alpha + kWheelBase / 2.0;
    const CosSin turn = turn_memo.get(alpha, Portable);
    const double local_x = (turn.c - 1.0) * radius;
    const double local_y = turn.s * radius;
    const CosSin rotation = CosSinMemo::compute<Portable>(pose.heading - kPi / 2.0);
    const double c = rotation.c;
    const double s = rotation.s;
    next.x += local_x * c - local_y * s;
    next.y += local_x * s + local_y * c;
    next.heading = normalize_angle(pose.heading + alpha);
    return next;
}

}  // namespace

Pose move_pose(const Pose& pose, double left, double right) {
    const double alpha = (right - left) / kWheelBase;

    // nearly equal wheels: a straight line of the left wheel's length
    if (std::fabs(alpha) <= 1e-10) {
        Pose next = pose;
        const CosSin heading = cos_sin(pose.heading);
        next.x += left * heading.c;
        next.y += left * heading.s;
        return next;
    }
    CosSinMemos& memos = current_memos();
    return memos.portable ? move_arc<true>(pose, left, alpha, memos.turn)
                          : move_arc<false>(pose, left, alpha, memos.turn);
}

bool is_still(const Pose& before, const Pose& after) {
    const double dx = after.x - before.x;
    const double dy = after.y - before.y;
    const double turn = std::fabs(normalize_angle(after.heading - before.heading));
    return dx * dx + dy * dy < kStillEpsilon * kStillEpsilon && turn < kStillEpsilon;
}

}  // namespace stepstone::sim
