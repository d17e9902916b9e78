// The arena's queries for lanes of episodes (sim::run_episode_queue): many
// robots at once, one per vector lane, each with its own door, every lane's
// arithmetic the single-robot query's. Each kernel is written once for a
// vector of W floats (GCC's vector extension) and compiled twice: four lanes
// a vector in the baseline build (SSE2), eight in an AVX2 function chosen
// at run time as the other AVX2 kernels are (avx2_kernels()). Both give the
// same bits: the same IEEE operations lane by lane, nothing contracted.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <utility>

#include "core/assert.hpp"
#include "sim/arena.hpp"
#include "sim/lane_load.hpp"
#include "sim/units.hpp"

namespace stepstone::sim {

namespace {

// (one specialisation a width: GCC drops a vector_size that depends on a template argument)
template <std::size_t W>
struct Vectors;
template <>
struct Vectors<4> {
    using Floats = float __attribute__((vector_size(16)));
    using Ints = std::int32_t __attribute__((vector_size(16)));
};
template <>
struct Vectors<8> {
    using Floats = float __attribute__((vector_size(32)));
    using Ints = std::int32_t __attribute__((vector_size(32)));
};

// where padding lanes stand: far from every wall (arena.cpp's empty slots are at +1e7)
constexpr float kNowhere = -1e7f;

// the walls as the kernels read them: each slot's box with the door closed, and the
// door's slot's box when it is open
struct Walls {
    const float* x0;
    const float* x1;
    const float* y0;
    const float* y1;
    std::size_t door;
    float open_door[4];  // x0, x1, y0, y1
};

// the kernels' view of an arena's padded slots (Slots, private to Arena, deduced)
template <class Slots>
Walls walls_of(const Slots& closed, const Slots& open, std::size_t door) {
    return {closed.x0.data(),
            closed.x1.data(),
            closed.y0.data(),
            closed.y1.data(),
            door,
            {open.x0[door], open.x1[door], open.y0[door], open.y1[door]}};
}

// Arena::NearGrid as the overlap kernel reads it (the grid is private to Arena)
struct NearCells {
    const std::uint32_t* cells;
    double x0;
    double y0;
    double inverse;  // 1 / Arena::NearGrid::kCell
    std::size_t columns;
    std::size_t rows;
    std::uint32_t all;  // every slot: a centre off the grid
};

// the slots a disc centred at (x, y) may come near: its cell's (found by a product: the cells
// were grown by a unit for it), every slot off the grid or for a NaN
std::uint32_t near_cell(const NearCells& grid, double x, double y) {
    const double column = (x - grid.x0) * grid.inverse;
    const double row = (y - grid.y0) * grid.inverse;
    if (!(column >= 0.0 && row >= 0.0 && column < static_cast<double>(grid.columns) &&
          row < static_cast<double>(grid.rows))) {
        return grid.all;
    }
    return grid.cells[static_cast<std::size_t>(row) * grid.columns + static_cast<std::size_t>(column)];
}

using lanes::load;

// slot k's box in every lane, the door's open box where `open` is set
template <class Floats, class Ints>
[[gnu::always_inline]] inline void box_of(const Walls& walls, std::size_t k, const Ints& open,
                                          Floats (&box)[4]) {
    const Floats zero = {};
    box[0] = zero + walls.x0[k];
    box[1] = zero + walls.x1[k];
    box[2] = zero + walls.y0[k];
    box[3] = zero + walls.y1[k];
    if (k != walls.door) return;
    for (std::size_t i = 0; i < 4; ++i) box[i] = open != 0 ? zero + walls.open_door[i] : box[i];
}

// ray_distance()'s guard against a zero component, in double before the conversion to float: the
// same float, as 1e-30 converts to 1e-30f
static_assert(static_cast<float>(1e-30) == 1e-30f);

// values[0, W) as W floats, with ray_distance()'s guard when kGuard: fabs(v) < 1e-30 becomes 1e-30
template <std::size_t W, bool kGuard, class Floats, std::size_t... I>
[[gnu::always_inline]] inline void floats_of(const double* values, Floats& out, std::index_sequence<I...>) {
    // a Floats' lanes as two halves of W/2
    using Doubles = typename lanes::DoubleVectors<W / 2>::Doubles;
    using HalfFloats = typename lanes::DoubleVectors<W / 2>::Floats;
    Doubles half[2];
    load(half[0], values);
    load(half[1], values + W / 2);
    if constexpr (kGuard) {
        for (Doubles& h : half) {
            const Doubles magnitude = h < 0.0 ? -h : h;  // only compared: -0.0 or 0.0 alike
            h = magnitude < 1e-30 ? Doubles{} + 1e-30 : h;
        }
    }
    const auto low = __builtin_convertvector(half[0], HalfFloats);
    const auto high = __builtin_convertvector(half[1], HalfFloats);
    out = __builtin_shufflevector(low, high, I...);
}

// out[0, W) = distances[0, W) converted to double where within `range`, else -1
template <std::size_t W, class Floats, std::size_t... I>
[[gnu::always_inline]] inline void distances_of(const Floats& distances, double range, double* out,
                                                std::index_sequence<I...>) {
    using Doubles = typename lanes::DoubleVectors<W / 2>::Doubles;
    const auto low = __builtin_shufflevector(distances, distances, I...);
    const auto high = __builtin_shufflevector(distances, distances, (I + W / 2)...);
    const Doubles d[2] = {__builtin_convertvector(low, Doubles), __builtin_convertvector(high, Doubles)};
    for (std::size_t h = 0; h < 2; ++h) {
        const Doubles kept = d[h] <= range ? d[h] : Doubles{} - 1.0;
        std::memcpy(out + h * (W / 2), &kept, sizeof kept);
    }
}

// The inputs of lanes [base, base + W), `in[k]` pointing at input k's lane `base`: read in
// place, or, for the last and partial block, copied into `block` with the padding at kNowhere
// (far from every wall; its results are never read) and `in` pointed there. True for a partial
// block.
template <std::size_t W, std::size_t N>
[[gnu::always_inline]] inline bool pad_block(const double* (&in)[N], std::size_t base, std::size_t count,
                                             double (&block)[N][W]) {
    if (base + W <= count) return false;
    for (std::size_t k = 0; k < N; ++k) {
        for (std::size_t i = 0; i < W; ++i) block[k][i] = base + i < count ? in[k][i] : kNowhere;
        in[k] = block[k];
    }
    return true;
}

// -1 in lane i of `open` where bit base + i of `door_open` is set (each lane's door)
template <std::size_t W, class Ints>
[[gnu::always_inline]] inline void doors_open(std::uint32_t door_open, std::size_t base, Ints& open) {
    Ints lane_bits;
    for (std::size_t i = 0; i < W; ++i) lane_bits[i] = static_cast<std::int32_t>(1u << i);
    open = ((Ints{} + static_cast<std::int32_t>(door_open >> base)) & lane_bits) != 0;
}

// Arena::disc_overlaps_lanes: near_slots()'s single-precision squared distance of each slot
// in turn, the smallest kept; the disc overlaps a wall when it is below r2. near[l] gets the
// slots (bit k) whose distance is below r2 + margin, near_slots()' `near`.
template <std::size_t W>
[[gnu::always_inline]] inline std::uint32_t overlaps_kernel(const Walls& walls, const NearCells& grid,
                                                            const double* x, const double* y,
                                                            std::uint32_t door_open, std::size_t count,
                                                            float margin, std::uint32_t* near) {
    using Floats = typename Vectors<W>::Floats;
    using Ints = typename Vectors<W>::Ints;
    const auto r2 = static_cast<float>(kRobotRadius * kRobotRadius);
    const float r2_near = r2 + margin;
    std::uint32_t bits = 0;
    for (std::size_t base = 0; base < count; base += W) {
        const double* centre[2] = {x + base, y + base};
        alignas(32) double block[2][W];
        const bool partial = pad_block(centre, base, count, block);
        Floats cx;
        Floats cy;
        floats_of<W, false>(centre[0], cx, std::make_index_sequence<W>{});
        floats_of<W, false>(centre[1], cy, std::make_index_sequence<W>{});
        Ints open;
        doors_open<W>(door_open, base, open);
        const Floats zero = {};
        Floats d2_min = zero + r2;
        Ints near_bits = {};
        // only the slots some lane's cell has near: the others are farther than the margin
        // from every lane (the padding's far centres come near none)
        std::uint32_t slots = 0;
        for (std::size_t i = base; i < base + W && i < count; ++i) slots |= near_cell(grid, x[i], y[i]);
        for (; slots != 0; slots &= slots - 1) {
            const auto k = static_cast<std::size_t>(std::countr_zero(slots));
            Floats box[4];
            box_of(walls, k, open, box);
            const Floats a = box[0] - cx;
            const Floats b = cx - box[1];
            const Floats c = box[2] - cy;
            const Floats d = cy - box[3];
            // std::max(std::max(a, b), 0.0f): (a < b ? b : a), then against 0 the same way
            const Floats ab = a < b ? b : a;
            const Floats cd = c < d ? d : c;
            const Floats ex = ab < zero ? zero : ab;
            const Floats ey = cd < zero ? zero : cd;
            const Floats d2 = ex * ex + ey * ey;
            d2_min = d2 < d2_min ? d2 : d2_min;
            near_bits |= (d2 < r2_near) & static_cast<std::int32_t>(1u << k);
        }
        const Ints below = d2_min < r2;
        std::uint32_t block_bits = 0;
        for (std::size_t i = 0; i < W; ++i) block_bits |= static_cast<std::uint32_t>(below[i] != 0) << i;
        bits |= block_bits << base;  // (the padding, far from every wall, sets none)
        if (!partial) {
            std::memcpy(near + base, &near_bits, sizeof near_bits);
        } else {
            alignas(32) std::uint32_t lanes_near[W];
            std::memcpy(lanes_near, &near_bits, sizeof near_bits);
            std::copy(lanes_near, lanes_near + (count - base), near + base);
        }
    }
    return bits;
}

// Arena::ray_distances_lanes: the slab test of ray_distances()' SSE kernel, slot after slot,
// the nearest hit kept as ray_distance() keeps it (std::min(nearest, t) in slot order); the
// origins and components converted to float, and the distances back, W lanes at a time
template <std::size_t W>
[[gnu::always_inline]] inline void rays_kernel(const Walls& walls, std::size_t slots, const double* x,
                                               const double* y, const double* const (&dx)[3],
                                               const double* const (&dy)[3], double range,
                                               std::uint32_t door_open, std::size_t count,
                                               double* const (&out)[3]) {
    using Floats = typename Vectors<W>::Floats;
    using Ints = typename Vectors<W>::Ints;
    constexpr float kNone = 1e30f;
    constexpr auto kAll = std::make_index_sequence<W>{};
    constexpr auto kHalf = std::make_index_sequence<W / 2>{};
    for (std::size_t base = 0; base < count; base += W) {
        const double* in[8] = {x + base, y + base};
        for (std::size_t r = 0; r < 3; ++r) {
            in[2 + 2 * r] = dx[r] + base;
            in[3 + 2 * r] = dy[r] + base;
        }
        alignas(32) double block[8][W];
        const bool partial = pad_block(in, base, count, block);
        Floats ox;
        Floats oy;
        floats_of<W, false>(in[0], ox, kAll);
        floats_of<W, false>(in[1], oy, kAll);
        Floats components[3][2];  // ray_distance()'s float components, guarded against 0
        for (std::size_t r = 0; r < 3; ++r) {
            floats_of<W, true>(in[2 + 2 * r], components[r][0], kAll);
            floats_of<W, true>(in[3 + 2 * r], components[r][1], kAll);
        }
        Ints open;
        doors_open<W>(door_open, base, open);
        const Floats zero = {};
        const Floats none = zero + kNone;
        Floats inverse[3][2];
        Floats nearest[3];
        for (std::size_t r = 0; r < 3; ++r) {
            for (std::size_t a = 0; a < 2; ++a) inverse[r][a] = (zero + 1.0f) / components[r][a];
            nearest[r] = none;
        }
        for (std::size_t k = 0; k < slots; ++k) {
            Floats box[4];
            box_of(walls, k, open, box);
            const Floats ax0 = box[0] - ox;
            const Floats ax1 = box[1] - ox;
            const Floats ay0 = box[2] - oy;
            const Floats ay1 = box[3] - oy;
            for (std::size_t r = 0; r < 3; ++r) {
                const Floats rx = inverse[r][0];
                const Floats ry = inverse[r][1];
                const Ints x_up = rx > zero;
                const Ints y_up = ry > zero;
                const Floats near_x = x_up != 0 ? ax0 : ax1;
                const Floats far_x = x_up != 0 ? ax1 : ax0;
                const Floats near_y = y_up != 0 ? ay0 : ay1;
                const Floats far_y = y_up != 0 ? ay1 : ay0;
                // _mm_max_ps(a, b) is a > b ? a : b, _mm_min_ps(a, b) is a < b ? a : b
                const Floats enter_y = near_y * ry;
                const Floats enter_x = near_x * rx;
                const Floats enter = enter_y > enter_x ? enter_y : enter_x;
                const Floats leave_y = far_y * ry;
                const Floats leave_x = far_x * rx;
                const Floats leave = leave_y < leave_x ? leave_y : leave_x;
                const Ints crossed = (enter <= leave) & (leave >= zero);
                const Floats from = zero > enter ? zero : enter;
                const Floats t = crossed != 0 ? from : none;
                nearest[r] = t < nearest[r] ? t : nearest[r];
            }
        }
        for (std::size_t r = 0; r < 3; ++r) {
            if (!partial) {
                distances_of<W>(nearest[r], range, out[r] + base, kHalf);
                continue;
            }
            alignas(32) double distances[W];
            distances_of<W>(nearest[r], range, distances, kHalf);
            std::copy(distances, distances + (count - base), out[r] + base);
        }
    }
}

#if defined(__x86_64__) || defined(__i386__)
#define STEPSTONE_SIM_HAVE_AVX2_LANES 1
[[gnu::target("avx2")]] std::uint32_t overlaps_avx2(const Walls& walls, const NearCells& grid,
                                                    const double* x, const double* y, std::uint32_t door_open,
                                                    std::size_t count, float margin, std::uint32_t* near) {
    return overlaps_kernel<8>(walls, grid, x, y, door_open, count, margin, near);
}

[[gnu::target("avx2")]] void rays_avx2(const Walls& walls, std::size_t slots, const double* x,
                                       const double* y, const double* const (&dx)[3],
                                       const double* const (&dy)[3], double range, std::uint32_t door_open,
                                       std::size_t count, double* const (&out)[3]) {
    rays_kernel<8>(walls, slots, x, y, dx, dy, range, door_open, count, out);
}
#endif

}  // namespace

std::uint32_t Arena::disc_overlaps_lanes(const double* x, const double* y, std::uint32_t door_open,
                                         std::size_t count, std::uint32_t* near) const {
    STEPSTONE_ASSERT(count <= 32);
    const Walls walls = walls_of(closed_, open_, static_cast<std::size_t>(door_index_));
    std::uint32_t ignored[32];
    if (near == nullptr) near = ignored;
    const NearCells grid{near_grid_.cells.data(), near_grid_.x0,   near_grid_.y0,      1.0 / NearGrid::kCell,
                         near_grid_.columns,      near_grid_.rows, (1u << kSlots) - 1u};
#ifdef STEPSTONE_SIM_HAVE_AVX2_LANES
    if (avx2_kernels()) return overlaps_avx2(walls, grid, x, y, door_open, count, kNearMargin, near);
#endif
    return overlaps_kernel<4>(walls, grid, x, y, door_open, count, kNearMargin, near);
}

void Arena::ray_distances_lanes(const double* x, const double* y, const double* const (&dx)[3],
                                const double* const (&dy)[3], double range, std::uint32_t door_open,
                                std::size_t count, double* const (&out)[3]) const {
    STEPSTONE_ASSERT(count <= 32);
    const Walls walls = walls_of(closed_, open_, static_cast<std::size_t>(door_index_));
    // the walls and the door only: an empty slot's box, far beyond any range, never gives a
    // distance (ray_distance() visits it and keeps none)
    const auto slots = static_cast<std::size_t>(wall_count_);
#ifdef STEPSTONE_SIM_HAVE_AVX2_LANES
    if (avx2_kernels()) return rays_avx2(walls, slots, x, y, dx, dy, range, door_open, count, out);
#endif
    rays_kernel<4>(walls, slots, x, y, dx, dy, range, door_open, count, out);
}

void Arena::build_near_grid() {
    // the walls' extent and a cell's margin beyond it: centres farther out are off the grid
    double lo_x = walls_[0].x0;
    double lo_y = walls_[0].y0;
    double hi_x = walls_[0].x1;
    double hi_y = walls_[0].y1;
    for (int k = 0; k < wall_count_; ++k) {
        const WallBox& box = walls_[static_cast<std::size_t>(k)];
        lo_x = std::min(lo_x, box.x0);
        lo_y = std::min(lo_y, box.y0);
        hi_x = std::max(hi_x, box.x1);
        hi_y = std::max(hi_y, box.y1);
    }
    const double reach = kRobotRadius + 2.0;  // the radius, its margin (under a unit) and a unit of slack
    near_grid_.x0 = lo_x - reach;
    near_grid_.y0 = lo_y - reach;
    const double columns = std::ceil((hi_x + reach - near_grid_.x0) / NearGrid::kCell);
    const double rows = std::ceil((hi_y + reach - near_grid_.y0) / NearGrid::kCell);
    // a spec ArenaSpec's parser accepts spans ~33 x 33 cells; anything far larger keeps no grid
    // (every centre off it: every slot visited)
    if (!(columns * rows <= 65'536.0)) return;
    near_grid_.columns = static_cast<std::size_t>(columns);
    near_grid_.rows = static_cast<std::size_t>(rows);
    near_grid_.cells.assign(near_grid_.columns * near_grid_.rows, 0u);
    for (std::size_t row = 0; row < near_grid_.rows; ++row) {
        for (std::size_t column = 0; column < near_grid_.columns; ++column) {
            // the cell grown by a unit: a centre's cell found by a product may be a neighbour's
            const double cx0 = near_grid_.x0 + static_cast<double>(column) * NearGrid::kCell - 1.0;
            const double cy0 = near_grid_.y0 + static_cast<double>(row) * NearGrid::kCell - 1.0;
            const double cx1 = cx0 + NearGrid::kCell + 2.0;
            const double cy1 = cy0 + NearGrid::kCell + 2.0;
            std::uint32_t near = 0;
            for (int k = 0; k < wall_count_; ++k) {  // the door as closed: the larger set
                const WallBox& box = walls_[static_cast<std::size_t>(k)];
                const double dx = std::max({box.x0 - cx1, cx0 - box.x1, 0.0});
                const double dy = std::max({box.y0 - cy1, cy0 - box.y1, 0.0});
                if (dx * dx + dy * dy < reach * reach) near |= 1u << k;
            }
            near_grid_.cells[row * near_grid_.columns + column] = near;
        }
    }
}

}  // namespace stepstone::sim
