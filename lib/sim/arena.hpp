#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "sim/arena_spec.hpp"
#include "sim/robot.hpp"

namespace stepstone::sim {

/// Whether the hot path uses its AVX2 kernels (lasers and light windows):
/// by default, when the CPU has AVX2. They compute the same bits as the SSE2
/// ones; tests switch them off to check those too.
bool avx2_kernels();
/// Turns the AVX2 kernels off, or back on where the CPU has AVX2. Not
/// synchronised: call it only while no simulation runs.
void set_avx2_kernels(bool on);

/// Result of testing the robot disc against the walls.
struct Contact {
    bool hit = false;    ///< the disc overlaps a wall
    bool left = false;   ///< some overlapping wall lies at a bearing in (0, pi/2): input 9
    bool right = false;  ///< some overlapping wall lies at a bearing in (-pi/2, 0): input 10
};

/// The walls of an arena (ArenaSpec): its fixed walls, then its door. The
/// default is the paper's (paper_arena(), decoded from the original's 296 x 296
/// px bitmap). Immutable; every query is const, allocation-free and thread-safe.
///
/// This is the hot-path geometry: the walls are kept in padded arrays (12 slots,
/// the door's slot replaced by an unreachable box when it is open) so every
/// query is a fixed-length loop of slab or clamp tests. ReferenceWorld
/// (reference/box2d_world.hpp) answers the same queries with Box2D.
class Arena {
public:
    /// Number of slots in the padded arrays.
    static constexpr int kSlots = 12;

    /// The paper's arena.
    Arena();
    /// The walls and door of `spec` (validated: at most kSlots boxes).
    explicit Arena(const ArenaSpec& spec);

    /// Every wall, the door included (its index is door_index()).
    std::span<const WallBox> walls() const { return {walls_.data(), static_cast<std::size_t>(wall_count_)}; }
    /// Index of the door box in walls(); the door is a wall only while closed.
    int door_index() const { return door_index_; }

    /// Distance in units from (x, y) along the unit direction (dx, dy) to the
    /// first wall, or -1 when no wall lies within `range`.
    double ray_distance(double x, double y, double dx, double dy, double range, bool door_open) const;
    /// ray_distance() for three rays from the same point at once (the
    /// lasers): `directions[i]` is ray i's unit direction, `out[i]` its result,
    /// bit-identical to three ray_distance() calls.
    void ray_distances(double x, double y, const double (&directions)[3][2], double range, bool door_open,
                       double (&out)[3]) const;
    /// True when a wall crosses the segment from (x0, y0) to (x1, y1).
    bool segment_blocked(double x0, double y0, double x1, double y1, bool door_open) const;
    /// The same test restricted to the walls whose bit is set in `walls`
    /// (bit i = walls()[i]); the door's bit is ignored while it is open.
    bool segment_blocked_by(std::uint32_t walls, double x0, double y0, double x1, double y1, bool door_open) const;
    /// True when the robot disc (kRobotRadius) centred at (x, y) overlaps a wall.
    bool disc_overlaps(double x, double y, bool door_open) const;
    /// disc_overlaps() of `count` (at most 32) centres at once: bit l is set when the disc at
    /// (x[l], y[l]) overlaps a wall, the door a wall unless bit l of `door_open` is set. The
    /// same single-precision test, one slot after the other across the centres. `near`, when
    /// given, gets `count` masks: the slots near lane l's disc, for contact_of_overlap().
    std::uint32_t disc_overlaps_lanes(const double* x, const double* y, std::uint32_t door_open,
                                      std::size_t count, std::uint32_t* near = nullptr) const;
    /// ray_distance() of three rays from each of `count` (at most 32) points at once: ray r of
    /// lane l starts at (x[l], y[l]) with the unit direction (dx[r][l], dy[r][l]), the door a
    /// wall unless bit l of `door_open` is set; out[r][l] gets ray_distance()'s bits.
    void ray_distances_lanes(const double* x, const double* y, const double* const (&dx)[3],
                             const double* const (&dy)[3], double range, std::uint32_t door_open,
                             std::size_t count, double* const (&out)[3]) const;
    /// Overlap test plus the bumpers: the bearing range, relative to the pose's
    /// heading, of each overlap region between the disc and a wall.
    Contact contact(const Pose& pose, bool door_open) const;
    /// contact() of a disc that overlaps a wall, `near` its mask from disc_overlaps_lanes(): the
    /// same answer without testing the overlap again.
    Contact contact_of_overlap(const Pose& pose, bool door_open, std::uint32_t near) const;
    /// contact() with every bearing from atan2, as first written; contact()
    /// decides most bumpers from the closest point and one segment test, the
    /// rest from signs of products, with the same answer (tests compare them).
    Contact contact_by_angles(const Pose& pose, bool door_open) const;
    /// contact() without its segment tests: the signs of products, then atan2.
    Contact contact_by_quarters(const Pose& pose, bool door_open) const;

private:
    // squared distance added to the radius's square for the walls the bumpers examine in
    // double precision
    static constexpr float kNearMargin = 1.0f;
    // single precision: four slots per SSE register; errors stay near 1e-4 units
    struct Slots {
        alignas(64) std::array<float, kSlots> x0, y0, x1, y1;
    };
    const Slots& slots(bool door_open) const { return door_open ? open_ : closed_; }
    // slots (bit k) the disc at (x, y) overlaps, and those within a margin of it
    struct Near {
        std::uint32_t overlap;
        std::uint32_t near;
    };
    Near near_slots(double x, double y, bool door_open) const;
    // contact()'s bumper bits (bit 0 left, bit 1 right) once the disc overlaps a wall; `near` as
    // near_slots() gives it (arena_bumpers.cpp)
    enum class BumperMethod { segments, quarters, angles };
    template <BumperMethod kMethod>
    [[gnu::noinline]] unsigned bumpers(const Pose& pose, bool door_open, std::uint32_t near) const;

    // the slots (bit k) whose box lies within the robot's radius and a slack of a cell of a
    // coarse grid over the walls: a superset of any disc_overlaps_lanes() near mask of a centre
    // in the cell (built in double, each cell grown by a unit, the radius by two units)
    struct NearGrid {
        static constexpr double kCell = 20.0;
        double x0 = 0.0;
        double y0 = 0.0;
        std::size_t columns = 0;
        std::size_t rows = 0;
        std::vector<std::uint32_t> cells;
    };
    void build_near_grid();

    std::array<WallBox, kSlots> walls_{};
    int wall_count_ = 0;
    int door_index_ = 0;
    Slots closed_{};
    Slots open_{};
    NearGrid near_grid_;
};

}  // namespace stepstone::sim
