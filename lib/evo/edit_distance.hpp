#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace stepstone::evo {

/// One sample of a discretised trajectory: a cell of the behaviour grid
/// (collectball: 12 x 12 cells of 50 x 50 units, docs/original.md: diversity).
struct GridCell {
    std::int16_t x = 0;
    std::int16_t y = 0;

    friend bool operator==(const GridCell&, const GridCell&) = default;
};

/// A trajectory: one cell per sample (80 in collectball).
using Trajectory = std::vector<GridCell>;

/// Divisor of the Manhattan distance in the substitution cost (collectball's NB_TILES).
inline constexpr float kGridTiles = 12.0f;

/// Substitution cost of collectball's edit distance (docs/original.md: diversity):
/// (|dx| + |dy|) / 12 in float, 0 for equal cells.
inline float substitution_cost(GridCell a, GridCell b) {
    const int dx = a.x > b.x ? a.x - b.x : b.x - a.x;
    const int dy = a.y > b.y ? a.y - b.y : b.y - a.y;
    return (static_cast<float>(dx) + static_cast<float>(dy)) / kGridTiles;
}

/// collectball's edit_dist (docs/original.md: diversity), an optimal-string-alignment
/// distance: insertion and deletion cost 1, substitution substitution_cost,
/// and the transposition of an adjacent swapped pair costs D[i-2][j-2] plus
/// the substitution cost of the current pair. Computed in float with three
/// reusable rows held by the object, so repeated calls do not allocate.
/// Every implementation below returns bit-identical values.
class EditDistance {
public:
    float operator()(std::span<const GridCell> a, std::span<const GridCell> b);

private:
    std::vector<float> rows_;
};

/// The same distance the original way: a fresh (|a|+1) x (|b|+1) table per
/// call. The baseline of `stepstone bench diversity`.
float edit_distance_full_table(std::span<const GridCell> a, std::span<const GridCell> b);

/// Number of pairs one batch computes side by side in vector lanes.
inline constexpr std::size_t kLanes = 16;

/// Distances of up to kLanes pairs (first[k], second[k]) at once, every
/// trajectory of the same `length`; lanes are independent and each equals
/// EditDistance exactly. Reuses its buffers across calls.
class EditDistanceBatch {
public:
    /// Vector instructions of run(): `automatic` uses AVX2 where the CPU has
    /// it, `baseline` only those of the build target (SSE2 on x86-64).
    enum class Simd : std::uint8_t { automatic, baseline };

    /// `simd` only affects speed, never a result.
    explicit EditDistanceBatch(Simd simd = Simd::automatic);

    /// Writes first.size() (<= kLanes) distances to `out`.
    void run(std::span<const GridCell* const> first, std::span<const GridCell* const> second,
             std::size_t length, float* out);

    /// Whether run() uses its AVX2 build (chosen at construction).
    bool uses_avx2() const { return avx2_; }

private:
    std::vector<float> ax_, ay_, bx_, by_, rows_;
    bool avx2_ = false;
};

}  // namespace stepstone::evo
