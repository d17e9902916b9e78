#include "sim/arena.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#if defined(__x86_64__) || defined(__i386__)
#define STEPSTONE_SIM_HAVE_AVX2_KERNEL 1
#include <immintrin.h>
#elif defined(__SSE__)
#include <xmmintrin.h>
#endif

#include "core/assert.hpp"
#include "core/cpu.hpp"
#include "core/error.hpp"
#include "core/text.hpp"
#include "sim/cos_sin.hpp"
#include "sim/units.hpp"

namespace stepstone::sim {

namespace {

// an empty slot: a box far away that no ray, segment or disc can reach
constexpr double kFar = 1e7;

// single-precision distances of points within kNearRange of the origin are off
// by far less than kNearMargin (arena.hpp)
constexpr double kNearRange = 1e4;

// bit k set when values[k] < limit
std::uint32_t less_mask(const std::array<float, Arena::kSlots>& values, float limit) {
    std::uint32_t bits = 0;
#if defined(__SSE__)
    const __m128 bound = _mm_set1_ps(limit);
    for (std::size_t k = 0; k < values.size(); k += 4) {
        bits |= static_cast<std::uint32_t>(_mm_movemask_ps(_mm_cmplt_ps(_mm_load_ps(&values[k]), bound))) << k;
    }
#else
    for (std::size_t k = 0; k < values.size(); ++k) bits |= static_cast<std::uint32_t>(values[k] < limit) << k;
#endif
    return bits;
}

// a direction component of exactly 0 would make 0 * inf = NaN in the slab test
double safe_inverse(double d) { return 1.0 / (d == 0.0 ? 1e-300 : d); }

bool cpu_has_avx2() {
#ifdef STEPSTONE_SIM_HAVE_AVX2_KERNEL
    return avx2_kernels_allowed();
#else
    return false;
#endif
}

bool g_avx2 = cpu_has_avx2();

#ifdef STEPSTONE_SIM_HAVE_AVX2_KERNEL
// ray_distances' SSE kernel in AVX2: slots 0-7 in one vector, 8-11 in a
// half one, every lane's operations the same. One self-contained function
// (no helper takes or returns a vector), so no 32-byte vector crosses into
// baseline code.
[[gnu::target("avx2")]] void rays_avx2(const float* x0, const float* y0, const float* x1, const float* y1, float ox,
                                       float oy, const float* inverses, float none, double range, double* out) {
    static_assert(Arena::kSlots == 12);
    alignas(32) float ax0[12], ax1[12], ay0[12], ay1[12];
    const __m256 vox = _mm256_set1_ps(ox);
    const __m256 voy = _mm256_set1_ps(oy);
    _mm256_store_ps(ax0, _mm256_sub_ps(_mm256_loadu_ps(x0), vox));
    _mm256_store_ps(ax1, _mm256_sub_ps(_mm256_loadu_ps(x1), vox));
    _mm256_store_ps(ay0, _mm256_sub_ps(_mm256_loadu_ps(y0), voy));
    _mm256_store_ps(ay1, _mm256_sub_ps(_mm256_loadu_ps(y1), voy));
    _mm_store_ps(ax0 + 8, _mm_sub_ps(_mm_loadu_ps(x0 + 8), _mm256_castps256_ps128(vox)));
    _mm_store_ps(ax1 + 8, _mm_sub_ps(_mm_loadu_ps(x1 + 8), _mm256_castps256_ps128(vox)));
    _mm_store_ps(ay0 + 8, _mm_sub_ps(_mm_loadu_ps(y0 + 8), _mm256_castps256_ps128(voy)));
    _mm_store_ps(ay1 + 8, _mm_sub_ps(_mm_loadu_ps(y1 + 8), _mm256_castps256_ps128(voy)));
    const __m256 zero = _mm256_setzero_ps();
    const __m256 vnone = _mm256_set1_ps(none);
    for (std::size_t r = 0; r < 3; ++r) {
        const float rx = inverses[2 * r];
        const float ry = inverses[2 * r + 1];
        const float* near_x = rx > 0.0f ? ax0 : ax1;
        const float* far_x = rx > 0.0f ? ax1 : ax0;
        const float* near_y = ry > 0.0f ? ay0 : ay1;
        const float* far_y = ry > 0.0f ? ay1 : ay0;
        const __m256 vrx = _mm256_set1_ps(rx);
        const __m256 vry = _mm256_set1_ps(ry);
        alignas(32) float hit[12];
        const __m256 enter = _mm256_max_ps(_mm256_mul_ps(_mm256_load_ps(near_y), vry),
                                           _mm256_mul_ps(_mm256_load_ps(near_x), vrx));
        const __m256 leave = _mm256_min_ps(_mm256_mul_ps(_mm256_load_ps(far_y), vry),
                                           _mm256_mul_ps(_mm256_load_ps(far_x), vrx));
        const __m256 crossed =
            _mm256_and_ps(_mm256_cmp_ps(enter, leave, _CMP_LE_OQ), _mm256_cmp_ps(leave, zero, _CMP_GE_OQ));
        const __m256 t = _mm256_blendv_ps(vnone, _mm256_max_ps(zero, enter), crossed);
        _mm256_store_ps(hit, t);
        const __m128 zero4 = _mm256_castps256_ps128(zero);
        const __m128 enter4 = _mm_max_ps(_mm_mul_ps(_mm_load_ps(near_y + 8), _mm256_castps256_ps128(vry)),
                                         _mm_mul_ps(_mm_load_ps(near_x + 8), _mm256_castps256_ps128(vrx)));
        const __m128 leave4 = _mm_min_ps(_mm_mul_ps(_mm_load_ps(far_y + 8), _mm256_castps256_ps128(vry)),
                                         _mm_mul_ps(_mm_load_ps(far_x + 8), _mm256_castps256_ps128(vrx)));
        const __m128 crossed4 =
            _mm_and_ps(_mm_cmp_ps(enter4, leave4, _CMP_LE_OQ), _mm_cmp_ps(leave4, zero4, _CMP_GE_OQ));
        const __m128 t4 =
            _mm_blendv_ps(_mm256_castps256_ps128(vnone), _mm_max_ps(zero4, enter4), crossed4);
        _mm_store_ps(hit + 8, t4);
        __m128 best = _mm_min_ps(_mm_min_ps(_mm256_castps256_ps128(t), _mm256_extractf128_ps(t, 1)), t4);
        best = _mm_min_ps(best, _mm_movehl_ps(best, best));
        best = _mm_min_ss(best, _mm_shuffle_ps(best, best, 1));
        float nearest = _mm_cvtss_f32(best);
        if (nearest == 0.0f) {
            nearest = none;
            for (const float h : hit) nearest = std::min(nearest, h);
        }
        out[r] = static_cast<double>(nearest) <= range ? static_cast<double>(nearest) : -1.0;
    }
}
#endif

}  // namespace

bool avx2_kernels() { return g_avx2; }

void set_avx2_kernels(bool on) { g_avx2 = on && cpu_has_avx2(); }

Arena::Arena() : Arena(paper_arena()) {}

Arena::Arena(const ArenaSpec& spec) {
    if (spec.walls.empty() || spec.walls.size() >= static_cast<std::size_t>(kSlots)) {
        throw ConfigError(concat("an arena holds 1 to ", kSlots - 1, " walls and a door, got ",
                                 spec.walls.size(), " walls"));
    }
    // the door comes last, so the open arena is the closed one minus its last box
    wall_count_ = static_cast<int>(spec.walls.size()) + 1;
    door_index_ = wall_count_ - 1;
    std::copy(spec.walls.begin(), spec.walls.end(), walls_.begin());
    walls_[static_cast<std::size_t>(door_index_)] = spec.door;
    const WallBox far{kFar, kFar, kFar + 1.0, kFar + 1.0, "empty"};
    auto put = [](Slots& slots, std::size_t k, const WallBox& box) {
        slots.x0[k] = static_cast<float>(box.x0);
        slots.y0[k] = static_cast<float>(box.y0);
        slots.x1[k] = static_cast<float>(box.x1);
        slots.y1[k] = static_cast<float>(box.y1);
    };
    for (int i = 0; i < kSlots; ++i) {
        const auto k = static_cast<std::size_t>(i);
        const bool real = i < wall_count_;
        put(closed_, k, real ? walls_[k] : far);
        put(open_, k, real && i != door_index_ ? walls_[k] : far);
    }
    build_near_grid();
}

double Arena::ray_distance(double x, double y, double dx, double dy, double range, bool door_open) const {
    const Slots& s = slots(door_open);
    const auto ox = static_cast<float>(x);
    const auto oy = static_cast<float>(y);
    // an axis-parallel ray gets a huge finite inverse: 0 * inf would be NaN
    const float ix = 1.0f / (std::fabs(dx) < 1e-30 ? 1e-30f : static_cast<float>(dx));
    const float iy = 1.0f / (std::fabs(dy) < 1e-30 ? 1e-30f : static_cast<float>(dy));
    constexpr float kNone = 1e30f;

    // slab test on every slot, written without branches or a reduction so the
    // compiler vectorises it: the ray enters a box at the latest slab entry
    // and leaves it at the earliest exit
    alignas(64) std::array<float, kSlots> hit;
    for (std::size_t k = 0; k < kSlots; ++k) {
        const float tx0 = (s.x0[k] - ox) * ix;
        const float tx1 = (s.x1[k] - ox) * ix;
        const float ty0 = (s.y0[k] - oy) * iy;
        const float ty1 = (s.y1[k] - oy) * iy;
        const float enter = std::max(std::min(tx0, tx1), std::min(ty0, ty1));
        const float leave = std::min(std::max(tx0, tx1), std::max(ty0, ty1));
        hit[k] = (enter <= leave) & (leave >= 0.0f) ? std::max(enter, 0.0f) : kNone;
    }
    float best = kNone;
    for (float t : hit) best = std::min(best, t);
    return static_cast<double>(best) <= range ? static_cast<double>(best) : -1.0;
}

void Arena::ray_distances(double x, double y, const double (&directions)[3][2], double range, bool door_open,
                          double (&out)[3]) const {
    const Slots& s = slots(door_open);
    const auto ox = static_cast<float>(x);
    const auto oy = static_cast<float>(y);
    // the float components with ray_distance's guard against a zero component
    float components[6];
    for (std::size_t r = 0; r < 3; ++r) {
        for (std::size_t a = 0; a < 2; ++a) {
            const double d = directions[r][a];
            components[2 * r + a] = std::fabs(d) < 1e-30 ? 1e-30f : static_cast<float>(d);
        }
    }
    constexpr float kNone = 1e30f;
#if defined(__SSE__)
    // ray_distance's slab test, every float operation the same, with three
    // shortcuts that leave each value's bits alone: one division instruction
    // takes four inverses; the offsets to each slot are shared by the rays;
    // and as a box's x0 < x1, the slab entry min(tx0, tx1) is tx0 when the
    // inverse is positive and tx1 when it is negative (the inverse is never
    // 0 and the two products are never both zero), so the entry and exit
    // need no min or max. The intrinsics' operand order follows std::min and
    // std::max: min(a, b) is _mm_min_ps(b, a), max(a, b) is _mm_max_ps(b, a).
    // (the vectors are assembled in registers: a vector load of scalars
    // just stored would stall on store forwarding)
    alignas(16) float inverses[8];
    const __m128 one = _mm_set1_ps(1.0f);
    _mm_store_ps(inverses,
                 _mm_div_ps(one, _mm_setr_ps(components[0], components[1], components[2], components[3])));
    _mm_store_ps(inverses + 4, _mm_div_ps(one, _mm_setr_ps(components[4], components[5], 1.0f, 1.0f)));
#ifdef STEPSTONE_SIM_HAVE_AVX2_KERNEL
    if (g_avx2) {
        return rays_avx2(s.x0.data(), s.y0.data(), s.x1.data(), s.y1.data(), ox, oy, inverses, kNone, range, out);
    }
#endif

    constexpr std::size_t kVectors = kSlots / 4;
    const __m128 vox = _mm_set1_ps(ox);
    const __m128 voy = _mm_set1_ps(oy);
    __m128 ax0[kVectors], ax1[kVectors], ay0[kVectors], ay1[kVectors];
    for (std::size_t v = 0; v < kVectors; ++v) {
        ax0[v] = _mm_sub_ps(_mm_load_ps(&s.x0[4 * v]), vox);
        ax1[v] = _mm_sub_ps(_mm_load_ps(&s.x1[4 * v]), vox);
        ay0[v] = _mm_sub_ps(_mm_load_ps(&s.y0[4 * v]), voy);
        ay1[v] = _mm_sub_ps(_mm_load_ps(&s.y1[4 * v]), voy);
    }
    const __m128 zero = _mm_setzero_ps();
    const __m128 none = _mm_set1_ps(kNone);
    for (std::size_t r = 0; r < 3; ++r) {
        const float rx = inverses[2 * r];
        const float ry = inverses[2 * r + 1];
        const __m128* near_x = rx > 0.0f ? ax0 : ax1;
        const __m128* far_x = rx > 0.0f ? ax1 : ax0;
        const __m128* near_y = ry > 0.0f ? ay0 : ay1;
        const __m128* far_y = ry > 0.0f ? ay1 : ay0;
        const __m128 vrx = _mm_set1_ps(rx);
        const __m128 vry = _mm_set1_ps(ry);
        alignas(16) float hit[kSlots];
        __m128 best = none;
        for (std::size_t v = 0; v < kVectors; ++v) {
            const __m128 enter = _mm_max_ps(_mm_mul_ps(near_y[v], vry), _mm_mul_ps(near_x[v], vrx));
            const __m128 leave = _mm_min_ps(_mm_mul_ps(far_y[v], vry), _mm_mul_ps(far_x[v], vrx));
            const __m128 crossed = _mm_and_ps(_mm_cmple_ps(enter, leave), _mm_cmpge_ps(leave, zero));
            const __m128 t = _mm_or_ps(_mm_and_ps(crossed, _mm_max_ps(zero, enter)), _mm_andnot_ps(crossed, none));
            _mm_store_ps(hit + 4 * v, t);
            best = _mm_min_ps(best, t);
        }
        best = _mm_min_ps(best, _mm_movehl_ps(best, best));
        best = _mm_min_ss(best, _mm_shuffle_ps(best, best, 1));
        float nearest = _mm_cvtss_f32(best);
        // the lanes' minimum in any order is the sequential one except for
        // the sign of a zero, which is the first zero's in slot order
        if (nearest == 0.0f) {
            nearest = kNone;
            for (const float t : hit) nearest = std::min(nearest, t);
        }
        out[r] = static_cast<double>(nearest) <= range ? static_cast<double>(nearest) : -1.0;
    }
#else
    float ix[3];
    float iy[3];
    for (std::size_t r = 0; r < 3; ++r) {
        ix[r] = 1.0f / components[2 * r];
        iy[r] = 1.0f / components[2 * r + 1];
    }

    // ray_distance's slab test with the offsets to each slot shared by the
    // three rays; every float operation is the one ray_distance performs
    alignas(64) std::array<float, kSlots> ax0, ax1, ay0, ay1;
    for (std::size_t k = 0; k < kSlots; ++k) {
        ax0[k] = s.x0[k] - ox;
        ax1[k] = s.x1[k] - ox;
        ay0[k] = s.y0[k] - oy;
        ay1[k] = s.y1[k] - oy;
    }
    alignas(64) std::array<float, kSlots> hit[3];
    for (std::size_t r = 0; r < 3; ++r) {
        const float rx = ix[r];
        const float ry = iy[r];
        for (std::size_t k = 0; k < kSlots; ++k) {
            const float tx0 = ax0[k] * rx;
            const float tx1 = ax1[k] * rx;
            const float ty0 = ay0[k] * ry;
            const float ty1 = ay1[k] * ry;
            const float enter = std::max(std::min(tx0, tx1), std::min(ty0, ty1));
            const float leave = std::min(std::max(tx0, tx1), std::max(ty0, ty1));
            hit[r][k] = (enter <= leave) & (leave >= 0.0f) ? std::max(enter, 0.0f) : kNone;
        }
    }
    for (std::size_t r = 0; r < 3; ++r) {
        float best = kNone;
        for (float t : hit[r]) best = std::min(best, t);
        out[r] = static_cast<double>(best) <= range ? static_cast<double>(best) : -1.0;
    }
#endif
}

namespace {

// one slab test of a segment against a box, parameter in [0, 1]
bool segment_hits(const WallBox& b, double x0, double y0, double ix, double iy) {
    const double tx0 = (b.x0 - x0) * ix;
    const double tx1 = (b.x1 - x0) * ix;
    const double ty0 = (b.y0 - y0) * iy;
    const double ty1 = (b.y1 - y0) * iy;
    const double enter = std::max(std::min(tx0, tx1), std::min(ty0, ty1));
    const double leave = std::min(std::max(tx0, tx1), std::max(ty0, ty1));
    return enter <= leave && leave >= 0.0 && enter <= 1.0;
}

}  // namespace

bool Arena::segment_blocked(double x0, double y0, double x1, double y1, bool door_open) const {
    return segment_blocked_by((1u << wall_count_) - 1u, x0, y0, x1, y1, door_open);
}

bool Arena::segment_blocked_by(std::uint32_t walls, double x0, double y0, double x1, double y1,
                               bool door_open) const {
    walls &= (1u << wall_count_) - 1u;
    if (door_open) walls &= ~(1u << door_index_);
    const double ix = safe_inverse(x1 - x0);
    const double iy = safe_inverse(y1 - y0);
    for (; walls != 0; walls &= walls - 1) {
        const auto k = static_cast<std::size_t>(std::countr_zero(walls));
        if (segment_hits(walls_[k], x0, y0, ix, iy)) return true;
    }
    return false;
}

inline Arena::Near Arena::near_slots(double x, double y, bool door_open) const {
    const Slots& s = slots(door_open);
    const auto cx = static_cast<float>(x);
    const auto cy = static_cast<float>(y);
    const auto r2 = static_cast<float>(kRobotRadius * kRobotRadius);
    // the centre's distance outside each box's x and y slabs, 0 inside; the
    // clamp at 0 and the squares in separate loops keep both in vector
    // registers (together, the compiler branches on the clamp)
    alignas(64) std::array<float, kSlots> ex;
    alignas(64) std::array<float, kSlots> ey;
    for (std::size_t k = 0; k < kSlots; ++k) {
        ex[k] = std::max(std::max(s.x0[k] - cx, cx - s.x1[k]), 0.0f);
        ey[k] = std::max(std::max(s.y0[k] - cy, cy - s.y1[k]), 0.0f);
    }
    alignas(64) std::array<float, kSlots> d2;
    for (std::size_t k = 0; k < kSlots; ++k) d2[k] = ex[k] * ex[k] + ey[k] * ey[k];
    return {less_mask(d2, r2), less_mask(d2, r2 + kNearMargin)};
}

bool Arena::disc_overlaps(double x, double y, bool door_open) const {
    return near_slots(x, y, door_open).overlap != 0;
}

namespace {

// the contact of a disc that overlaps a wall, from the bumpers' bits (bit 0 left, bit 1 right,
// arena_bumpers.cpp): they become bools here, where the caller can keep them in registers
Contact overlap_contact(unsigned sides) { return Contact{true, (sides & 1u) != 0, (sides & 2u) != 0}; }

}  // namespace

// the common case, no overlap, returns before any of the bumpers' work
Contact Arena::contact(const Pose& pose, bool door_open) const {
    const Near near = near_slots(pose.x, pose.y, door_open);
    if (near.overlap == 0) return Contact{};
    return contact_of_overlap(pose, door_open, near.near);
}

Contact Arena::contact_of_overlap(const Pose& pose, bool door_open, std::uint32_t near) const {
    return overlap_contact(bumpers<BumperMethod::segments>(pose, door_open, near));
}

Contact Arena::contact_by_angles(const Pose& pose, bool door_open) const {
    const Near near = near_slots(pose.x, pose.y, door_open);
    if (near.overlap == 0) return Contact{};
    return overlap_contact(bumpers<BumperMethod::angles>(pose, door_open, near.near));
}

Contact Arena::contact_by_quarters(const Pose& pose, bool door_open) const {
    const Near near = near_slots(pose.x, pose.y, door_open);
    if (near.overlap == 0) return Contact{};
    return overlap_contact(bumpers<BumperMethod::quarters>(pose, door_open, near.near));
}

}  // namespace stepstone::sim
