#include "sim/robot.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "core/portable_math_lanes.hpp"
#include "sim/arena.hpp"
#include "sim/cos_sin.hpp"
#include "sim/lane_load.hpp"
#include "sim/units.hpp"

namespace stepstone::sim {

double normalize_angle(double angle) {
    // headings change by at most 0.2 rad per step, so one wrap is the common case
    while (angle > kPi) angle -= 2.0 * kPi;
    while (angle <= -kPi) angle += 2.0 * kPi;
    return angle;
}

namespace {

// a move's angles, one expression each for move_pose() and move_lanes()
double turn_of(double left, double right) { return (right - left) / kWheelBase; }
bool is_straight(double alpha) { return std::fabs(alpha) <= 1e-10; }
double rotation_of(const Pose& pose) { return pose.heading - kPi / 2.0; }
double heading_after(const Pose& pose, double alpha) { return normalize_angle(pose.heading + alpha); }

// the arc of a turning move, with the run's sin and cos known at compile time (one branch a move)
template <bool Portable>
Pose move_arc(const Pose& pose, double left, double alpha, CosSinMemos& memos) {
    Pose next = pose;
    // an arc about the instantaneous centre, computed in the robot frame
    // (forward = local +y) and rotated by heading - pi/2 into the world
    const double radius = left / alpha + kWheelBase / 2.0;
    const CosSin turn = memos.turn.get(alpha, Portable);
    const double local_x = (turn.c - 1.0) * radius;
    const double local_y = turn.s * radius;
    const CosSin rotation = CosSinMemo::compute<Portable>(rotation_of(pose));
    const double c = rotation.c;
    const double s = rotation.s;
    next.x += local_x * c - local_y * s;
    next.y += local_x * s + local_y * c;
    next.heading = heading_after(pose, alpha);
    return next;
}

using lanes::load;

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

namespace {

// move_lanes() W lanes a vector: every expression as move_pose()'s, both of its branches
// computed and one chosen by lane
template <std::size_t W>
[[gnu::always_inline]] inline void move_kernel(MoveLanes& lanes) {
    using Doubles = typename lanes::DoubleVectors<W>::Doubles;
    using Floats = typename lanes::DoubleVectors<W>::Floats;
    using Longs = typename lanes::DoubleVectors<W>::Longs;
    constexpr std::size_t kWidth = W;
    constexpr std::size_t kMax = MoveLanes::kMaxLanes;
    const std::size_t n = lanes.count;
    const std::size_t padded = (n + kWidth - 1) / kWidth * kWidth;
    for (std::size_t l = n; l < padded; ++l) {  // padding lanes: a straight move from the origin
        lanes.x[l] = lanes.y[l] = lanes.heading[l] = 0.0;
        lanes.left[l] = lanes.right[l] = 0.5f;
    }
    // the angles: the new heading of every lane, then the turn and the rotation of every lane
    // (asked for in every lane; a straight lane ignores them), `padded` apart so that one call
    // takes their sines and cosines
    // (no initialiser: the loop below writes every lane sincos_lanes() reads, padding included)
    alignas(64) std::array<double, 3 * kMax> angles;
    alignas(64) std::array<double, 3 * kMax> sines;
    alignas(64) std::array<double, 3 * kMax> cosines;
    alignas(64) std::array<double, kMax> left;
    Longs wrapped_twice = {};
    for (std::size_t l = 0; l < padded; l += kWidth) {
        Floats left_output;
        Floats right_output;
        Doubles heading;
        load(left_output, &lanes.left[l]);
        load(right_output, &lanes.right[l]);
        load(heading, &lanes.heading[l]);
        // wheel_step() and turn_of()
        const Doubles a = 4.0 * (2.0 * __builtin_convertvector(left_output, Doubles) - 1.0);
        const Doubles b = 4.0 * (2.0 * __builtin_convertvector(right_output, Doubles) - 1.0);
        const Doubles alpha = (b - a) / kWheelBase;
        // normalize_angle()'s loops, once each: a heading in (-pi, pi] plus a turn of at most
        // 0.2 rad wraps at most once (checked below)
        Doubles h = heading + alpha;
        h = h > kPi ? h - 2.0 * kPi : h;
        h = h <= -kPi ? h + 2.0 * kPi : h;
        wrapped_twice |= (h > kPi) | (h <= -kPi);
        const Longs straight = (alpha <= 1e-10) & (alpha >= -1e-10);  // is_straight(): fabs(alpha) <= 1e-10
        const Doubles next = straight != 0 ? heading : h;
        const Doubles rotation = heading - kPi / 2.0;
        std::memcpy(&left[l], &a, sizeof a);
        std::memcpy(&angles[l], &next, sizeof next);
        std::memcpy(&angles[padded + l], &alpha, sizeof alpha);
        std::memcpy(&angles[2 * padded + l], &rotation, sizeof rotation);
    }
    bool any_wrapped_twice = false;
    for (std::size_t i = 0; i < kWidth; ++i) any_wrapped_twice |= wrapped_twice[i] != 0;
    if (any_wrapped_twice) {
        for (std::size_t l = 0; l < n; ++l) {
            const double alpha = angles[padded + l];
            if (!is_straight(alpha)) angles[l] = heading_after(Pose{0.0, 0.0, lanes.heading[l]}, alpha);
        }
    }
    // (GCC cannot tell that the loop above wrote all 3 * padded angles)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
    portable::sincos_lanes(angles.data(), sines.data(), cosines.data(), 3 * padded);
#pragma GCC diagnostic pop
    for (std::size_t l = 0; l < padded; l += kWidth) {
        Doubles a, alpha, hc, hs, tc, ts, rc, rs, x0, y0;
        load(a, &left[l]);
        load(alpha, &angles[padded + l]);
        load(hc, &cosines[l]);
        load(hs, &sines[l]);
        load(tc, &cosines[padded + l]);
        load(ts, &sines[padded + l]);
        load(rc, &cosines[2 * padded + l]);
        load(rs, &sines[2 * padded + l]);
        load(x0, &lanes.x[l]);
        load(y0, &lanes.y[l]);
        // move_arc()'s arithmetic
        const Doubles radius = a / alpha + kWheelBase / 2.0;
        const Doubles local_x = (tc - 1.0) * radius;
        const Doubles local_y = ts * radius;
        const Longs straight = (alpha <= 1e-10) & (alpha >= -1e-10);
        const Doubles x = x0 + (straight != 0 ? a * hc : local_x * rc - local_y * rs);
        const Doubles y = y0 + (straight != 0 ? a * hs : local_x * rs + local_y * rc);
        std::memcpy(&lanes.next_x[l], &x, sizeof x);
        std::memcpy(&lanes.next_y[l], &y, sizeof y);
        std::memcpy(&lanes.next_cos[l], &hc, sizeof hc);
        std::memcpy(&lanes.next_sin[l], &hs, sizeof hs);
    }
    std::copy(angles.begin(), angles.begin() + static_cast<std::ptrdiff_t>(n), lanes.next_heading.begin());
}

void move_sse2(MoveLanes& lanes) { move_kernel<2>(lanes); }

#if defined(__x86_64__) || defined(__i386__)
#define STEPSTONE_SIM_HAVE_AVX2_MOVE 1
[[gnu::target("avx2")]] void move_avx2(MoveLanes& lanes) { move_kernel<4>(lanes); }
#endif

}  // namespace

void move_lanes(MoveLanes& lanes) {
#ifdef STEPSTONE_SIM_HAVE_AVX2_MOVE
    if (avx2_kernels()) return move_avx2(lanes);
#endif
    move_sse2(lanes);
}

bool is_still(const Pose& before, const Pose& after) {
    const double dx = after.x - before.x;
    const double dy = after.y - before.y;
    const double turn = std::fabs(normalize_angle(after.heading - before.heading));
    return dx * dx + dy * dy < kStillEpsilon * kStillEpsilon && turn < kStillEpsilon;
}

}  // namespace stepstone::sim
