#include "sim/sensors.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#if defined(__x86_64__) || defined(__i386__)
#define STEPSTONE_SIM_HAVE_AVX2_KERNEL 1
#include <immintrin.h>
#elif defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "core/assert.hpp"
#include "core/error.hpp"
#include "core/text.hpp"
#include "sim/cos_sin.hpp"
#include "sim/units.hpp"

namespace stepstone::sim {

namespace {

// the edges of a window as unit vectors in the robot frame (x forward, y
// towards positive bearings): a bearing lies strictly inside the window when
// it is strictly counter-clockwise of the first and clockwise of the second
struct Window {
    double lo_x, lo_y, hi_x, hi_y;
};

Window window_of(double angle, bool portable) {
    const CosSin lo = CosSinMemo::compute(angle - kLightWindow / 2, portable);
    const CosSin hi = CosSinMemo::compute(angle + kLightWindow / 2, portable);
    return {lo.c, lo.s, hi.c, hi.s};
}

// The -pi/4 window is the +pi/4 one mirrored: its edges are at exactly
// minus the other's (angle -a +- w/2 rounds to -(a -+ w/2)), and cos and sin
// are even and odd bit for bit, so its edge vectors are the other's with the
// y components negated. Then the four cross products share two pairs of
// products: with A = lo_y u, B = lo_x v, P = hi_y u, Q = hi_x v (the +pi/4
// window's edges), the +pi/4 tests are B - A > 0 and P - Q > 0, the -pi/4
// ones Q - (-P) > 0 and (-A) - B > 0, and a difference of two finite
// doubles is positive exactly when the first is larger.
bool same_bits(double a, double b) { return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b); }

// the two windows' edges with the functions of a run (std::cos and std::sin, or
// portable::sincos), and whether they mirror each other bit for bit
struct Windows {
    Window w[2];
    bool mirrored;
};

Windows windows_of(bool portable) {
    const Window plus = window_of(kLightSensorAngles[0], portable);
    const Window minus = window_of(kLightSensorAngles[1], portable);
    const bool mirrored = same_bits(minus.lo_x, plus.hi_x) && same_bits(minus.lo_y, -plus.hi_y) &&
                          same_bits(minus.hi_x, plus.lo_x) && same_bits(minus.hi_y, -plus.lo_y);
    return {{plus, minus}, mirrored};
}

const Windows kLibmWindows = windows_of(false);
const Windows kPortableWindows = windows_of(true);

const Windows& windows_for(const CosSinMemos& memos) {
    return memos.portable ? kPortableWindows : kLibmWindows;
}

// bit i set when a[i] > 0 and b[i] > 0: inside()'s two tests, slot by slot
std::uint32_t positive_pairs(const std::array<double, kMaxLights>& a, const std::array<double, kMaxLights>& b) {
    std::uint32_t bits = 0;
#if defined(__SSE2__)
    const __m128d zero = _mm_setzero_pd();
    for (std::size_t i = 0; i < a.size(); i += 2) {
        const __m128d both = _mm_and_pd(_mm_cmpgt_pd(_mm_load_pd(&a[i]), zero), _mm_cmpgt_pd(_mm_load_pd(&b[i]), zero));
        bits |= static_cast<std::uint32_t>(_mm_movemask_pd(both)) << i;
    }
#else
    for (std::size_t i = 0; i < a.size(); ++i) {
        bits |= static_cast<std::uint32_t>((a[i] > 0.0) & (b[i] > 0.0)) << i;
    }
#endif
    return bits;
}

#ifdef STEPSTONE_SIM_HAVE_AVX2_KERNEL
// the mirrored window tests of sense() in AVX2, four slots per vector, every
// lane's operations the same as in the SSE2 loop; `edges` is the +pi/4
// window's lo_x, lo_y, hi_x, hi_y; a group of four slots without a bit of
// `wanted` is skipped (its bits stay 0). Self-contained: no vector crosses
// into baseline code.
[[gnu::target("avx2")]] void window_masks_avx2(const double* xs, const double* ys, std::size_t count,
                                               std::uint32_t wanted, double x, double y, double c, double s,
                                               const double* edges, std::uint32_t& plus,
                                               std::uint32_t& minus) {
    const __m256d vc = _mm256_set1_pd(c);
    const __m256d vs = _mm256_set1_pd(s);
    const __m256d px = _mm256_set1_pd(x);
    const __m256d py = _mm256_set1_pd(y);
    const __m256d lo_x = _mm256_set1_pd(edges[0]);
    const __m256d lo_y = _mm256_set1_pd(edges[1]);
    const __m256d hi_x = _mm256_set1_pd(edges[2]);
    const __m256d hi_y = _mm256_set1_pd(edges[3]);
    const __m256d sign = _mm256_set1_pd(-0.0);
    std::uint32_t in_plus = 0;
    std::uint32_t in_minus = 0;
    for (std::size_t i = 0; i < count; i += 4) {
        if (((wanted >> i) & 0xFu) == 0) continue;  // four slots no answer needs
        const __m256d dx = _mm256_sub_pd(_mm256_loadu_pd(xs + i), px);
        const __m256d dy = _mm256_sub_pd(_mm256_loadu_pd(ys + i), py);
        const __m256d u = _mm256_add_pd(_mm256_mul_pd(dx, vc), _mm256_mul_pd(dy, vs));
        const __m256d v = _mm256_sub_pd(_mm256_mul_pd(dy, vc), _mm256_mul_pd(dx, vs));
        const __m256d a = _mm256_mul_pd(lo_y, u);
        const __m256d b = _mm256_mul_pd(lo_x, v);
        const __m256d p = _mm256_mul_pd(hi_y, u);
        const __m256d q = _mm256_mul_pd(hi_x, v);
        const __m256d both_plus = _mm256_and_pd(_mm256_cmp_pd(b, a, _CMP_GT_OQ), _mm256_cmp_pd(p, q, _CMP_GT_OQ));
        const __m256d both_minus = _mm256_and_pd(_mm256_cmp_pd(q, _mm256_xor_pd(p, sign), _CMP_GT_OQ),
                                                 _mm256_cmp_pd(_mm256_xor_pd(a, sign), b, _CMP_GT_OQ));
        in_plus |= static_cast<std::uint32_t>(_mm256_movemask_pd(both_plus)) << i;
        in_minus |= static_cast<std::uint32_t>(_mm256_movemask_pd(both_minus)) << i;
    }
    plus = in_plus;
    minus = in_minus;
}
#endif

bool inside(const Window& w, double u, double v) {
    // both sides evaluated: no branch on the first outcome
    return (w.lo_x * v - w.lo_y * u > 0.0) & (u * w.hi_y - v * w.hi_x > 0.0);
}

constexpr const char* kChannelNames[kChannels] = {
    "laser_p45",  "laser_m45",   "laser_0",     "ball_p45",    "ball_m45",   "basket_p45",
    "basket_m45", "switch_p45",  "switch_m45",  "bumper_left", "bumper_right", "carrying",
    "left_wheel", "right_wheel", "action",
};

}  // namespace

namespace {

// the three lasers at +pi/4, -pi/4 and 0, from the heading's cosine and sine:
// rotations by the fixed angles
void sense_lasers(const Arena& arena, const Pose& pose, double c, double s, bool door_open, SensorReadings& out) {
    constexpr double kHalfRoot2 = 0.70710678118654752440;
    const double dirs[3][2] = {{(c - s) * kHalfRoot2, (s + c) * kHalfRoot2},
                               {(c + s) * kHalfRoot2, (s - c) * kHalfRoot2},
                               {c, s}};
    double distances[3];
    arena.ray_distances(pose.x, pose.y, dirs, kLaserRange, door_open, distances);
    for (std::size_t i = 0; i < 3; ++i) out.laser[i] = distances[i];
}

// lasers, then lights culled by colour already seen and by the windows before
// any line of sight; `blocked(index, light)` answers the sight-line question
template <class Blocked>
void sense_with(const Arena& arena, std::span<const Light> lights, const Pose& pose, const WorldState& state,
                SensorReadings& out, Blocked&& blocked) {
    STEPSTONE_ASSERT(lights.size() <= static_cast<std::size_t>(kMaxLights));
    CosSinMemos& memos = current_memos();  // one thread-local read for the windows and the heading
    const Windows& windows = windows_for(memos);
    const CosSin heading = memos.heading.get(pose.heading, memos.portable);
    const double c = heading.c;
    const double s = heading.s;
    sense_lasers(arena, pose, c, s, state.door_open, out);

    out.light = {};
    for (std::uint32_t lit = state.lit; lit != 0; lit &= lit - 1) {
        const auto index = static_cast<std::size_t>(std::countr_zero(lit));
        if (index >= lights.size()) break;
        const Light& light = lights[index];
        const std::size_t first = 2 * static_cast<std::size_t>(light.kind);
        if (out.light[first] && out.light[first + 1]) continue;
        const double dx = light.x - pose.x;
        const double dy = light.y - pose.y;
        const double u = dx * c + dy * s;
        const double v = dy * c - dx * s;
        const bool plus = !out.light[first] && inside(windows.w[0], u, v);
        const bool minus = !out.light[first + 1] && inside(windows.w[1], u, v);
        if (!plus && !minus) continue;
        if (blocked(index, light)) continue;
        out.light[first] = out.light[first] || plus;
        out.light[first + 1] = out.light[first + 1] || minus;
    }
}

// the hull of a light and a cell can meet a wall only if no axis separates
// them; the axes tried are the cell's and the normals of the light-to-corner
// lines, a superset of the hull's edge normals
bool hull_meets(const Light& light, double cx0, double cy0, double cx1, double cy1, const WallBox& wall) {
    const double px[5] = {light.x, cx0, cx1, cx0, cx1};
    const double py[5] = {light.y, cy0, cy0, cy1, cy1};
    const double wx[4] = {wall.x0, wall.x1, wall.x0, wall.x1};
    const double wy[4] = {wall.y0, wall.y0, wall.y1, wall.y1};
    auto separated = [&](double ax, double ay) {
        double plo = 1e300, phi = -1e300, wlo = 1e300, whi = -1e300;
        for (int i = 0; i < 5; ++i) {
            const double p = px[i] * ax + py[i] * ay;
            plo = std::min(plo, p);
            phi = std::max(phi, p);
        }
        for (int i = 0; i < 4; ++i) {
            const double p = wx[i] * ax + wy[i] * ay;
            wlo = std::min(wlo, p);
            whi = std::max(whi, p);
        }
        // a small margin keeps the table conservative against rounding
        return phi < wlo - 1e-6 || whi < plo - 1e-6;
    };
    if (separated(1.0, 0.0) || separated(0.0, 1.0)) return false;
    for (int i = 1; i < 5; ++i) {
        const double ex = px[i] - light.x;
        const double ey = py[i] - light.y;
        if ((ex != 0.0 || ey != 0.0) && separated(-ey, ex)) return false;
    }
    return true;
}

// true when the segment from the light to each corner of the cell crosses
// the wall shrunk by kHiddenMargin: then every segment from the light to the
// cell crosses the wall itself, deep enough for the slab test's rounding
bool hides(const Light& light, double cx0, double cy0, double cx1, double cy1, const WallBox& wall) {
    constexpr double m = SightTable::kHiddenMargin;
    const double x0 = wall.x0 + m;
    const double y0 = wall.y0 + m;
    const double x1 = wall.x1 - m;
    const double y1 = wall.y1 - m;
    if (!(x0 < x1 && y0 < y1)) return false;
    for (const double px : {cx0, cx1}) {
        for (const double py : {cy0, cy1}) {
            const double dx = px - light.x;
            const double dy = py - light.y;
            if (dx == 0.0 || dy == 0.0) return false;  // the slab form below needs both
            const double tx0 = (x0 - light.x) / dx;
            const double tx1 = (x1 - light.x) / dx;
            const double ty0 = (y0 - light.y) / dy;
            const double ty1 = (y1 - light.y) / dy;
            const double enter = std::max(std::min(tx0, tx1), std::min(ty0, ty1));
            const double leave = std::min(std::max(tx0, tx1), std::max(ty0, ty1));
            if (!(enter <= leave && leave >= 0.0 && enter <= 1.0)) return false;
        }
    }
    return true;
}

}  // namespace

SightTable::SightTable(const Arena& arena, std::span<const Light> lights) : lights_(lights.begin(), lights.end()) {
    if (lights.size() > static_cast<std::size_t>(kMaxLights)) {
        throw DataError(concat("a task may have at most ", kMaxLights, " lights, got ", lights.size()));
    }
    for (std::size_t l = 0; l < lights_.size(); ++l) {
        xs_[l] = lights_[l].x;
        ys_[l] = lights_[l].y;
        kinds_[static_cast<std::size_t>(lights_[l].kind)] |= 1u << l;
    }
    const auto walls = arena.walls();
    constexpr std::size_t kCells = static_cast<std::size_t>(kColumns) * kRows;
    masks_.assign((kCells + 1) * kMaxLights, 0);
    summaries_.assign(kCells + 1, Summary{});
    std::fill(masks_.begin() + static_cast<std::ptrdiff_t>(kCells * kMaxLights), masks_.end(), std::uint16_t{0xffff});
    reach_.assign(kCells, 0);
    for (std::size_t l = 0; l < lights_.size(); ++l) {
        for (int row = 0; row < kRows; ++row) {
            for (int column = 0; column < kColumns; ++column) {
                // the reach disc against the cell grown by a unit: the squared distance from the
                // light to the grown cell's closest point, with a unit's slack on the radius too
                const double px = std::clamp(lights_[l].x, column * kCell - 1.0, (column + 1) * kCell + 1.0);
                const double py = std::clamp(lights_[l].y, row * kCell - 1.0, (row + 1) * kCell + 1.0);
                const double dx = px - lights_[l].x;
                const double dy = py - lights_[l].y;
                if (dx * dx + dy * dy < (kReach + 1.0) * (kReach + 1.0)) {
                    reach_[static_cast<std::size_t>(row) * kColumns + static_cast<std::size_t>(column)] |=
                        1u << l;
                }
                std::uint16_t mask = 0;
                for (std::size_t w = 0; w < walls.size(); ++w) {
                    if (hull_meets(lights_[l], column * kCell, row * kCell, (column + 1) * kCell, (row + 1) * kCell,
                                   walls[w])) {
                        mask = static_cast<std::uint16_t>(mask | (1u << w));
                    }
                }
                const std::size_t cell = static_cast<std::size_t>(row) * kColumns + static_cast<std::size_t>(column);
                masks_[cell * kMaxLights + l] = mask;
                Summary& summary = summaries_[cell];
                if (mask == 0) summary.clear |= 1u << l;
                for (std::uint32_t rest = mask; rest != 0; rest &= rest - 1) {
                    const auto w = static_cast<std::size_t>(std::countr_zero(rest));
                    if (!hides(lights_[l], column * kCell, row * kCell, (column + 1) * kCell, (row + 1) * kCell,
                               walls[w])) {
                        continue;
                    }
                    if (static_cast<int>(w) == arena.door_index()) {
                        summary.hidden_by_door |= 1u << l;
                    } else {
                        summary.hidden_by_fixed |= 1u << l;
                    }
                }
            }
        }
    }
}

std::size_t SightTable::cell_index(double x, double y) const {
    // column floor(x / kCell), row floor(y / kCell): a floor is below n
    // exactly when its argument is, and on the grid the quotients are not
    // negative, so truncation gives their floor
    const double column = x / kCell;
    const double row = y / kCell;
    if (!(column >= 0.0 && column < kColumns && row >= 0.0 && row < kRows)) {
        return static_cast<std::size_t>(kColumns) * kRows;
    }
    const auto whole_row = static_cast<std::size_t>(static_cast<int>(row));
    const auto whole_column = static_cast<std::size_t>(static_cast<int>(column));
    return whole_row * kColumns + whole_column;
}

std::uint32_t SightTable::candidates(std::size_t index, double x, double y) const {
    STEPSTONE_ASSERT(index < lights_.size());
    const std::size_t cell = cell_index(x, y);
    if (cell == static_cast<std::size_t>(kColumns) * kRows) return ~0u;
    return masks_[cell * kMaxLights + index];
}

SightTable::Cell SightTable::cell(double x, double y, bool door_open) const {
    const std::size_t index = cell_index(x, y);
    const Summary& summary = summaries_[index];
    const std::uint32_t hidden = summary.hidden_by_fixed | (door_open ? 0u : summary.hidden_by_door);
    return {masks_.data() + index * kMaxLights, summary.clear, hidden};
}

// the hot path: the lights the sight table's cell hides dropped, the window tests of
// every other lit light, without branches on their outcome, then per colour a clear
// light in a window settles the sensor, and only the remaining lights test their
// candidate walls
void sense(const Arena& arena, const SightTable& sight, const Pose& pose, const WorldState& state,
           SensorReadings& out) {
    const CosSin heading = cos_sin(pose.heading);
    sense_lasers(arena, pose, heading.c, heading.s, state.door_open, out);
    sense_lights(arena, sight, pose, state, out);
}

void sense_lasers_lanes(const Arena& arena, const double* x, const double* y, const double* c,
                        const double* s, std::uint32_t door_open, std::size_t count,
                        double* const (&out)[3]) {
    STEPSTONE_ASSERT(count <= 32);
    // sense_lasers()' directions, lane by lane
    constexpr double kHalfRoot2 = 0.70710678118654752440;
    alignas(64) double dx[3][32];
    alignas(64) double dy[3][32];
    for (std::size_t l = 0; l < count; ++l) {
        dx[0][l] = (c[l] - s[l]) * kHalfRoot2;
        dy[0][l] = (s[l] + c[l]) * kHalfRoot2;
        dx[1][l] = (c[l] + s[l]) * kHalfRoot2;
        dy[1][l] = (s[l] - c[l]) * kHalfRoot2;
        dx[2][l] = c[l];
        dy[2][l] = s[l];
    }
    arena.ray_distances_lanes(x, y, {dx[0], dx[1], dx[2]}, {dy[0], dy[1], dy[2]}, kLaserRange, door_open,
                              count, out);
}

void sense_lights(const Arena& arena, const SightTable& sight, const Pose& pose, const WorldState& state,
                  SensorReadings& out) {
    CosSinMemos& memos = current_memos();  // one thread-local read for the windows and the heading
    const Windows& windows = windows_for(memos);
    const CosSin heading = memos.heading.get(pose.heading, memos.portable);
    const double c = heading.c;
    const double s = heading.s;

    out.light = {};
    // the lit lights that a wall does not hide from the whole cell: the others never fire a sensor
    const SightTable::Cell cell = sight.cell(pose.x, pose.y, state.door_open);
    const std::uint32_t lit = state.lit & ((1u << sight.lights().size()) - 1u) & ~cell.hidden;
    if (lit == 0) return;
    const auto& xs = sight.xs();
    const auto& ys = sight.ys();
    std::uint32_t plus = 0;
    std::uint32_t minus = 0;
#ifdef STEPSTONE_SIM_HAVE_AVX2_KERNEL
    if (windows.mirrored && avx2_kernels()) {
        // padded to kMaxLights, a multiple of 4: the last vector stays inside
        static_assert(kMaxLights % 4 == 0);
        const double edges[4] = {windows.w[0].lo_x, windows.w[0].lo_y, windows.w[0].hi_x, windows.w[0].hi_y};
        window_masks_avx2(xs.data(), ys.data(), sight.lights().size(), lit, pose.x, pose.y, c, s, edges, plus,
                          minus);
    } else
#endif
#if defined(__SSE2__)
        if (windows.mirrored) {
        // the window tests of two slots per vector, up to the last light
        const __m128d vc = _mm_set1_pd(c);
        const __m128d vs = _mm_set1_pd(s);
        const __m128d px = _mm_set1_pd(pose.x);
        const __m128d py = _mm_set1_pd(pose.y);
        const __m128d lo_x = _mm_set1_pd(windows.w[0].lo_x);
        const __m128d lo_y = _mm_set1_pd(windows.w[0].lo_y);
        const __m128d hi_x = _mm_set1_pd(windows.w[0].hi_x);
        const __m128d hi_y = _mm_set1_pd(windows.w[0].hi_y);
        const __m128d sign = _mm_set1_pd(-0.0);
        const std::size_t count = sight.lights().size();
        for (std::size_t i = 0; i < count; i += 2) {
            const __m128d dx = _mm_sub_pd(_mm_loadu_pd(&xs[i]), px);
            const __m128d dy = _mm_sub_pd(_mm_loadu_pd(&ys[i]), py);
            const __m128d u = _mm_add_pd(_mm_mul_pd(dx, vc), _mm_mul_pd(dy, vs));
            const __m128d v = _mm_sub_pd(_mm_mul_pd(dy, vc), _mm_mul_pd(dx, vs));
            const __m128d a = _mm_mul_pd(lo_y, u);
            const __m128d b = _mm_mul_pd(lo_x, v);
            const __m128d p = _mm_mul_pd(hi_y, u);
            const __m128d q = _mm_mul_pd(hi_x, v);
            const __m128d in_plus = _mm_and_pd(_mm_cmpgt_pd(b, a), _mm_cmpgt_pd(p, q));
            const __m128d in_minus =
                _mm_and_pd(_mm_cmpgt_pd(q, _mm_xor_pd(p, sign)), _mm_cmpgt_pd(_mm_xor_pd(a, sign), b));
            plus |= static_cast<std::uint32_t>(_mm_movemask_pd(in_plus)) << i;
            minus |= static_cast<std::uint32_t>(_mm_movemask_pd(in_minus)) << i;
        }
    } else
#endif
    {
        // the window edges' cross products for every padded slot, in a loop
        // the compiler vectorises; their signs become the light masks below
        alignas(64) std::array<double, kMaxLights> plus_lo;
        alignas(64) std::array<double, kMaxLights> plus_hi;
        alignas(64) std::array<double, kMaxLights> minus_lo;
        alignas(64) std::array<double, kMaxLights> minus_hi;
        for (std::size_t i = 0; i < static_cast<std::size_t>(kMaxLights); ++i) {
            const double dx = xs[i] - pose.x;
            const double dy = ys[i] - pose.y;
            const double u = dx * c + dy * s;
            const double v = dy * c - dx * s;
            plus_lo[i] = windows.w[0].lo_x * v - windows.w[0].lo_y * u;
            plus_hi[i] = u * windows.w[0].hi_y - v * windows.w[0].hi_x;
            minus_lo[i] = windows.w[1].lo_x * v - windows.w[1].lo_y * u;
            minus_hi[i] = u * windows.w[1].hi_y - v * windows.w[1].hi_x;
        }
        plus = positive_pairs(plus_lo, plus_hi);
        minus = positive_pairs(minus_lo, minus_hi);
    }
    // the lit mask drops the slots that hold no lit light, or a hidden one
    plus &= lit;
    minus &= lit;
    if ((plus | minus) == 0) return;

    for (std::size_t kind = 0; kind < 3; ++kind) {
        const std::uint32_t in_plus = plus & sight.kinds()[kind];
        const std::uint32_t in_minus = minus & sight.kinds()[kind];
        bool seen_plus = (in_plus & cell.clear) != 0;
        bool seen_minus = (in_minus & cell.clear) != 0;
        // (the hidden lights are out of `lit` already)
        for (std::uint32_t rest = (in_plus | in_minus) & ~cell.clear; rest != 0; rest &= rest - 1) {
            const int i = std::countr_zero(rest);
            const bool p = ((in_plus >> i) & 1u) != 0;
            const bool m = ((in_minus >> i) & 1u) != 0;
            if (!(p && !seen_plus) && !(m && !seen_minus)) continue;
            const auto k = static_cast<std::size_t>(i);
            if (arena.segment_blocked_by(cell.walls[k], xs[k], ys[k], pose.x, pose.y, state.door_open)) continue;
            seen_plus = seen_plus || p;
            seen_minus = seen_minus || m;
        }
        out.light[2 * kind] = seen_plus;
        out.light[2 * kind + 1] = seen_minus;
    }
}

void sense(const Arena& arena, std::span<const Light> lights, const Pose& pose, const WorldState& state,
           SensorReadings& out) {
    sense_with(arena, lights, pose, state, out, [&](std::size_t, const Light& light) {
        return arena.segment_blocked(light.x, light.y, pose.x, pose.y, state.door_open);
    });
}

std::span<const char* const> channel_names() { return kChannelNames; }

}  // namespace stepstone::sim
