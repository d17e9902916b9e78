#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

#include "sim/arena.hpp"
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
// the relative margin by which the sign tests below must be clear of a quarter's edge to be sure
constexpr double kQuarterMargin = 1e-9;

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
    struct Offset {
        double dx, dy;
    };
    Offset in[4] = {};  // an offset seen in each quarter: (0, pi/2), (pi/2, pi), (-pi, -pi/2), (-pi/2, 0)
    unsigned seen = 0;
    bool sure = true;
    auto classify = [&](double dx, double dy) {
        const double u = dx * c + dy * s;
        const double v = dy * c - dx * s;
        const double margin = kQuarterMargin * (std::fabs(u) + std::fabs(v));
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
        const double margin =
            kQuarterMargin * (std::fabs(a.dx) + std::fabs(a.dy)) * (std::fabs(b.dx) + std::fabs(b.dy));
        sure = sure && std::fabs(cross) > margin;
        return cross > 0.0;
    };
    const bool left = (seen & 1u) != 0 || ((seen & 0b1010u) == 0b1010u && counter_clockwise(in[3], in[1]));
    const bool right = (seen & 8u) != 0 || ((seen & 0b0101u) == 0b0101u && counter_clockwise(in[2], in[0]));
    return (left ? kLeft : 0u) | (right ? kRight : 0u) | (sure ? kSure : 0u);
}

// bumpers_by_quarters' answer from the closest point and one segment's test against the box,
// with kSure set when it is sure of it (the common case: no vertex is computed). Let R be the
// overlap region and P the closest point, clearly in a quarter (u, v as bumpers_by_quarters
// takes them). R is convex and its bearings lie within pi/2 of P's, so P's quarter settles one
// bumper: in (0, pi/2) the left one is pressed, in (pi/2, pi) the right one is not, and so on.
// The other bumper asks whether R reaches the next quarter (the one asked), across the radius g
// between the two; h is the unit normal of g towards the quarter asked, and P lies beyond h = -e:
//   - if the segment {h = -e, g in [0, r]} misses the box, R stays on P's side by e: it would
//     otherwise hold a point of that segment (on the chord from P to any point beyond);
//   - if the segment {h = +e, g in [e, r - e]} (inside the disc) meets the box, R holds a point
//     of it, in the quarter asked by e.
// e = 1e-6 is far above the 1e-9 relative margin bumpers_by_quarters keeps from a quarter's edge
// (e / r = 5e-8), and each segment test is taken only when it is clear by kSlack (1e-9 units,
// far above the rounding of coordinates below 1e4), so the answer is the one atan2 gives.
// Segment against box: separated along x, along y or along h (the separating axes of a segment
// and a box), by the largest gap; both overlap when every gap is negative.
unsigned bumpers_by_segments(const WallBox& box, const Pose& pose, double c, double s, double px, double py) {
    constexpr double kOffset = 1e-6;
    constexpr double kSlack = 1e-9;
    const double dx = px - pose.x;
    const double dy = py - pose.y;
    const double u = dx * c + dy * s;
    const double v = dy * c - dx * s;
    const double margin = kQuarterMargin * (std::fabs(u) + std::fabs(v));
    if (!(std::fabs(u) > margin && std::fabs(v) > margin)) return 0;
    // forward f = (c, s), left n = (-s, c)
    unsigned known = 0;  // the bumper P's quarter presses, if any
    unsigned asked = 0;
    double gx, gy, hx, hy;
    if (u > 0.0) {  // (0, pi/2) or (-pi/2, 0): the forward radius, towards the other side
        gx = c;
        gy = s;
        known = v > 0.0 ? kLeft : kRight;
        asked = v > 0.0 ? kRight : kLeft;
        hx = v > 0.0 ? s : -s;
        hy = v > 0.0 ? -c : c;
    } else {  // (pi/2, pi) or (-pi, -pi/2): the left or right radius, towards the front
        gx = v > 0.0 ? -s : s;
        gy = v > 0.0 ? c : -c;
        asked = v > 0.0 ? kLeft : kRight;
        hx = c;
        hy = s;
    }
    if (!(hx * dx + hy * dy < -(kOffset + kSlack))) return 0;
    // the box's extent along h, from the centre
    const double x0 = box.x0 - pose.x;
    const double x1 = box.x1 - pose.x;
    const double y0 = box.y0 - pose.y;
    const double y1 = box.y1 - pose.y;
    const double h_lo = std::min(hx * x0, hx * x1) + std::min(hy * y0, hy * y1);
    const double h_hi = std::max(hx * x0, hx * x1) + std::max(hy * y0, hy * y1);
    // the largest gap between the box and the segment {h = a, g in [t0, t1]}
    const auto gap = [&](double a, double t0, double t1) {
        const double ax = a * hx + t0 * gx;
        const double ay = a * hy + t0 * gy;
        const double bx = a * hx + t1 * gx;
        const double by = a * hy + t1 * gy;
        const double gap_x = std::max(x0 - std::max(ax, bx), std::min(ax, bx) - x1);
        const double gap_y = std::max(y0 - std::max(ay, by), std::min(ay, by) - y1);
        const double gap_h = std::max(h_lo - a, a - h_hi);
        return std::max(std::max(gap_x, gap_y), gap_h);
    };
    if (gap(-kOffset, 0.0, kRobotRadius) > kSlack) return known | kSure;
    if (gap(kOffset, kOffset, kRobotRadius - kOffset) < -kSlack) return known | asked | kSure;
    return 0;
}

}  // namespace

template <Arena::BumperMethod kMethod>
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
        if constexpr (kMethod != BumperMethod::angles) {
            if (d2 > 1e-20) {
                const CosSin heading = cos_sin(pose.heading);
                if constexpr (kMethod == BumperMethod::segments)
                    wall_sides = bumpers_by_segments(box, pose, heading.c, heading.s, px, py);
                if ((wall_sides & kSure) == 0)
                    wall_sides = bumpers_by_quarters(box, pose, heading.c, heading.s, px, py);
            }
        }
        if ((wall_sides & kSure) == 0) wall_sides = bumpers_by_angles(box, pose, px, py);
        sides |= wall_sides & (kLeft | kRight);
    }
    return sides;
}

template unsigned Arena::bumpers<Arena::BumperMethod::segments>(const Pose&, bool, std::uint32_t) const;
template unsigned Arena::bumpers<Arena::BumperMethod::quarters>(const Pose&, bool, std::uint32_t) const;
template unsigned Arena::bumpers<Arena::BumperMethod::angles>(const Pose&, bool, std::uint32_t) const;

}  // namespace stepstone::sim
