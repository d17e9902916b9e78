#include "sim/arena.hpp"

#include <bit>
#include <cmath>
#include <cstdint>

#include "sim/cos_sin.hpp"
#include "sim/robot.hpp"
#include "sim/units.hpp"

// Arena::bumpers: which bumpers a disc that overlaps a wall presses (arena.cpp finds the overlap)
namespace stepstone::sim {

namespace {

double clamp(double v, double lo, double hi) { return v < lo ? lo : (v > hi ? hi : v); }

// the vertices of the region where the disc centred at (cx, cy) overlaps the
// box: box corners inside the disc and edge/circle crossings; `vertex(dx, dy)`
// gets each one's offset from the centre. The extremes of the region's
// bearings (it is convex) are at these vertices.
template <class Vertex>
void overlap_vertices(const WallBox& box, double cx, double cy, Vertex&& vertex) {
    const double r2 = kRobotRadius * kRobotRadius;
    const double xs[2] = {box.x0, box.x1};
    const double ys[2] = {box.y0, box.y1};
    for (double x : xs) {
        for (double y : ys) {
            if ((x - cx) * (x - cx) + (y - cy) * (y - cy) < r2) vertex(x - cx, y - cy);
        }
    }
    for (double x : xs) {  // vertical edges
        const double h2 = r2 - (x - cx) * (x - cx);
        if (h2 <= 0.0) continue;
        const double h = std::sqrt(h2);
        for (double y : {cy - h, cy + h}) {
            if (y >= box.y0 && y <= box.y1) vertex(x - cx, y - cy);
        }
    }
    for (double y : ys) {  // horizontal edges
        const double h2 = r2 - (y - cy) * (y - cy);
        if (h2 <= 0.0) continue;
        const double h = std::sqrt(h2);
        for (double x : {cx - h, cx + h}) {
            if (x >= box.x0 && x <= box.x1) vertex(x - cx, y - cy);
        }
    }
}

// the bearing range [lo, hi] (radians, relative to `reference`) under which
// the centre sees the part of the box inside the disc
void overlap_bearings(const WallBox& box, double cx, double cy, double reference, double& lo, double& hi) {
    lo = 0.0;
    hi = 0.0;
    overlap_vertices(box, cx, cy, [&](double dx, double dy) {
        const double rel = normalize_angle(evaluation_atan2(dy, dx) - reference);
        lo = std::min(lo, rel);
        hi = std::max(hi, rel);
    });
}

// true when the bearing interval [lo, hi] (radians, any winding) meets the open interval (a, b)
bool meets(double lo, double hi, double a, double b) {
    for (double shift : {-2.0 * kPi, 0.0, 2.0 * kPi}) {
        if (lo + shift < b && hi + shift > a) return true;
    }
    return false;
}

// bumper bits: left (input 9), right (input 10), and the answer is sure
constexpr unsigned kLeft = 1;
constexpr unsigned kRight = 2;
constexpr unsigned kSure = 4;

// the bumpers of one wall the disc overlaps without containing the centre
// ((px, py) is the wall's point closest to it): the bearing range of the
// overlap region from atan2, relative to the closest point's bearing (which
// lies inside it), then whether it meets each quarter
unsigned bumpers_by_angles(const WallBox& box, const Pose& pose, double px, double py) {
    const double closest = evaluation_atan2(py - pose.y, px - pose.x);
    double lo = 0.0;
    double hi = 0.0;
    overlap_bearings(box, pose.x, pose.y, closest, lo, hi);
    const double base = normalize_angle(closest - pose.heading);
    return (meets(base + lo, base + hi, 0.0, kPi / 2) ? kLeft : 0u) |
           (meets(base + lo, base + hi, -kPi / 2, 0.0) ? kRight : 0u);
}

// bumpers_by_angles' answer without atan2, with kSure set when it is sure
// of it. In the robot frame (u forward, v towards positive bearings, from the
// heading's cosine c and sine s), each vertex of the overlap region and the
// closest point fall in a quarter by the signs of u and v. The region's
// bearings form an arc shorter than pi (all lie within pi/2 of the closest
// point's), whose ends are vertices; it meets the open quarter (0, pi/2) when
// a vertex lies in it, or when the arc runs from a vertex in (-pi/2, 0)
// counter-clockwise to one in (pi/2, pi) (the cross product of their offsets
// is positive); (-pi/2, 0) likewise. Every sign is taken only when it is
// clear by a relative margin of 1e-9, far above the rounding of both this
// arithmetic and atan2's, so the answer is the one atan2's bearings give;
// a vertex within the margin of a quarter's edge leaves it to atan2.
unsigned bumpers_by_quarters(const WallBox& box, const Pose& pose, double c, double s, double px, double py) {
    constexpr double kMargin = 1e-9;
    struct Offset {
        double dx, dy;
    };
    Offset in[4] = {};  // an offset seen in each quarter: (0, pi/2), (pi/2, pi), (-pi, -pi/2), (-pi/2, 0)
    unsigned seen = 0;
    bool sure = true;
    auto classify = [&](double dx, double dy) {
        const double u = dx * c + dy * s;
        const double v = dy * c - dx * s;
        const double margin = kMargin * (std::fabs(u) + std::fabs(v));
        sure = sure && std::fabs(u) > margin && std::fabs(v) > margin;
        const unsigned quarter = u > 0.0 ? (v > 0.0 ? 0u : 3u) : (v > 0.0 ? 1u : 2u);
        seen |= 1u << quarter;
        in[quarter] = {dx, dy};
    };
    classify(px - pose.x, py - pose.y);
    overlap_vertices(box, pose.x, pose.y, classify);
    // true when the arc from a's bearing counter-clockwise to b's is shorter than pi
    auto counter_clockwise = [&](const Offset& a, const Offset& b) {
        const double cross = a.dx * b.dy - a.dy * b.dx;
        const double margin = kMargin * (std::fabs(a.dx) + std::fabs(a.dy)) * (std::fabs(b.dx) + std::fabs(b.dy));
        sure = sure && std::fabs(cross) > margin;
        return cross > 0.0;
    };
    const bool left = (seen & 1u) != 0 || ((seen & 0b1010u) == 0b1010u && counter_clockwise(in[3], in[1]));
    const bool right = (seen & 8u) != 0 || ((seen & 0b0101u) == 0b0101u && counter_clockwise(in[2], in[0]));
    return (left ? kLeft : 0u) | (right ? kRight : 0u) | (sure ? kSure : 0u);
}

}  // namespace

template <bool kByAngles>
unsigned Arena::bumpers(const Pose& pose, bool door_open, std::uint32_t near) const {
    unsigned sides = 0;
    const double r2 = kRobotRadius * kRobotRadius;
    // the walls the exact test below can find within the radius: those the
    // single-precision distances put within the margin, every wall far from
    // the map where single precision is too coarse for the margin
    const bool on_map = std::fabs(pose.x) < kNearRange && std::fabs(pose.y) < kNearRange;
    std::uint32_t walls = on_map ? near : (1u << wall_count_) - 1u;
    if (door_open) walls &= ~(1u << door_index_);
    for (; walls != 0 && sides != (kLeft | kRight); walls &= walls - 1) {
        const WallBox& box = walls_[static_cast<std::size_t>(std::countr_zero(walls))];
        const double px = clamp(pose.x, box.x0, box.x1);
        const double py = clamp(pose.y, box.y0, box.y1);
        const double d2 = (px - pose.x) * (px - pose.x) + (py - pose.y) * (py - pose.y);
        if (d2 >= r2) continue;

        // a centre inside a wall sees it all around
        if (d2 == 0.0) {
            sides = kLeft | kRight;
            continue;
        }

        // (a centre within 1e-10 of the wall is left to atan2: the offsets
        // stay far from underflow)
        unsigned wall_sides = 0;
        if constexpr (!kByAngles) {
            if (d2 > 1e-20) {
                const CosSin heading = cos_sin(pose.heading);
                wall_sides = bumpers_by_quarters(box, pose, heading.c, heading.s, px, py);
            }
        }
        if ((wall_sides & kSure) == 0) wall_sides = bumpers_by_angles(box, pose, px, py);
        sides |= wall_sides & (kLeft | kRight);
    }
    return sides;
}

template unsigned Arena::bumpers<false>(const Pose&, bool, std::uint32_t) const;
template unsigned Arena::bumpers<true>(const Pose&, bool, std::uint32_t) const;

}  // namespace stepstone::sim
