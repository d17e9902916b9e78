#pragma once

namespace stepstone::sim {

/// Position (units) and heading (radians in (-pi, pi], 0 = +x, positive = towards +y).
struct Pose {
    double x = 0.0;
    double y = 0.0;
    double heading = 0.0;

    bool operator==(const Pose&) const = default;
};

/// Wraps an angle into (-pi, pi], radians.
double normalize_angle(double angle);

/// Wheel displacement in units for one step from a controller output in [0, 1]:
/// 4 (2 o - 1).
inline double wheel_step(float output) { return 4.0 * (2.0 * static_cast<double>(output) - 1.0); }

/// Exact differential-drive arc odometry (fastsim's Posture::move): the pose
/// after the left and right wheels moved `left` and `right` units, with the
/// wheels kWheelBase apart. Collisions are not considered.
Pose move_pose(const Pose& pose, double left, double right);

/// The angles move_pose() takes cos and sin of, and the heading it gives
/// (the one the sensors take them of next): a straight move (|turn| <= 1e-10)
/// asks only for the heading's, which it keeps; an arc for the turn's and for
/// those of heading - pi/2 (the rotation into the world). The lanes of
/// sim::run_episode_queue compute them for several moves at once.
struct MoveAngles {
    bool arc = false;
    double turn = 0.0;
    double rotation = 0.0;  ///< heading - pi/2 (an arc only)
    double heading = 0.0;   ///< the heading after the move
};
MoveAngles move_angles(const Pose& pose, double left, double right);

/// True when the change from `before` to `after` is below kStillEpsilon both in
/// distance and in heading (the stand-still rule).
bool is_still(const Pose& before, const Pose& after);

}  // namespace stepstone::sim
