#pragma once

#include <array>
#include <cstddef>

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

/// The moves of up to kMaxLanes episodes at once, structure of arrays: the
/// lanes of sim::run_episode_queue in a portable run. Fill count, the poses
/// and the clamped wheel outputs; move_lanes() writes the poses move_pose()
/// gives (collisions not considered) and the cos and sin of each new heading,
/// every value with portable::sincos's bits, as the scalar portable path.
struct MoveLanes {
    static constexpr std::size_t kMaxLanes = 32;
    std::size_t count = 0;
    alignas(64) std::array<double, kMaxLanes> x{};
    alignas(64) std::array<double, kMaxLanes> y{};
    alignas(64) std::array<double, kMaxLanes> heading{};
    alignas(64) std::array<float, kMaxLanes> left{};   ///< clamped output 0
    alignas(64) std::array<float, kMaxLanes> right{};  ///< clamped output 1
    // written by move_lanes()
    alignas(64) std::array<double, kMaxLanes> next_x{};
    alignas(64) std::array<double, kMaxLanes> next_y{};
    alignas(64) std::array<double, kMaxLanes> next_heading{};
    alignas(64) std::array<double, kMaxLanes> next_cos{};  ///< cos(next_heading)
    alignas(64) std::array<double, kMaxLanes> next_sin{};  ///< sin(next_heading)
};

/// move_pose() of every lane with wheel_step() of its outputs and portable::sincos
/// (portable::sincos_lanes): the same doubles as the scalar portable path, one
/// branch-free loop over the lanes for the angles and one for the poses.
void move_lanes(MoveLanes& lanes);

/// True when the change from `before` to `after` is below kStillEpsilon both in
/// distance and in heading (the stand-still rule).
bool is_still(const Pose& before, const Pose& after);

}  // namespace stepstone::sim
