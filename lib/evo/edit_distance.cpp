#include "evo/edit_distance.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>

#include "core/assert.hpp"

namespace stepstone::evo {

namespace {

inline float min3(float a, float b, float c) {
    const float ab = b < a ? b : a;
    return c < ab ? c : ab;
}

// four float lanes with GCC's vector extensions (plain SSE2, no ABI change)
typedef float V4 __attribute__((vector_size(16)));
typedef std::int32_t M4 __attribute__((vector_size(16)));

inline V4 load(const float* p) {
    V4 v;
    std::memcpy(&v, p, sizeof v);
    return v;
}

inline void store(float* p, V4 v) { std::memcpy(p, &v, sizeof v); }

// the same selection as min3, lane by lane
inline V4 vmin(V4 a, V4 b) { return b < a ? b : a; }

inline V4 vabs(V4 a) { return std::bit_cast<V4>(std::bit_cast<M4>(a) & 0x7fffffff); }

}  // namespace

float EditDistance::operator()(std::span<const GridCell> a, std::span<const GridCell> b) {
    const std::size_t n = a.size();
    const std::size_t m = b.size();
    const std::size_t width = m + 1;
    rows_.resize(3 * width);

    // rows i-2, i-1 and i rotate through the three slots
    float* before = rows_.data();
    float* previous = before + width;
    float* current = previous + width;
    for (std::size_t j = 0; j <= m; ++j) previous[j] = static_cast<float>(j);

    for (std::size_t i = 1; i <= n; ++i) {
        current[0] = static_cast<float>(i);
        for (std::size_t j = 1; j <= m; ++j) {
            const float cost = substitution_cost(a[i - 1], b[j - 1]);
            float d = min3(previous[j] + 1.0f, current[j - 1] + 1.0f, previous[j - 1] + cost);
            // an adjacent swapped pair, priced at the current substitution cost (collectball)
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) {
                const float swapped = before[j - 2] + cost;
                d = swapped < d ? swapped : d;
            }
            current[j] = d;
        }
        std::swap(before, previous);
        std::swap(previous, current);
    }
    return previous[m];
}

float edit_distance_full_table(std::span<const GridCell> a, std::span<const GridCell> b) {
    const std::size_t n = a.size();
    const std::size_t m = b.size();
    std::vector<std::vector<float>> table(n + 1, std::vector<float>(m + 1, 0.0f));
    for (std::size_t i = 0; i <= n; ++i) table[i][0] = static_cast<float>(i);
    for (std::size_t j = 0; j <= m; ++j) table[0][j] = static_cast<float>(j);
    for (std::size_t i = 1; i <= n; ++i) {
        for (std::size_t j = 1; j <= m; ++j) {
            const float cost = substitution_cost(a[i - 1], b[j - 1]);
            table[i][j] = min3(table[i - 1][j] + 1.0f, table[i][j - 1] + 1.0f, table[i - 1][j - 1] + cost);
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) {
                table[i][j] = std::min(table[i][j], table[i - 2][j - 2] + cost);
            }
        }
    }
    return table[n][m];
}

void EditDistanceBatch::run(std::span<const GridCell* const> first, std::span<const GridCell* const> second,
                            std::size_t length, float* out) {
    constexpr std::size_t L = kLanes;
    static_assert(L % 4 == 0);
    const std::size_t count = first.size();
    STEPSTONE_ASSERT(count == second.size() && count >= 1 && count <= L);
    const std::size_t n = length;
    const std::size_t width = n + 1;

    // cells as floats, lane-interleaved; unused lanes repeat lane 0
    ax_.resize(n * L);
    ay_.resize(n * L);
    bx_.resize(n * L);
    by_.resize(n * L);
    for (std::size_t l = 0; l < L; ++l) {
        const GridCell* a = first[l < count ? l : 0];
        const GridCell* b = second[l < count ? l : 0];
        for (std::size_t i = 0; i < n; ++i) {
            ax_[i * L + l] = a[i].x;
            ay_[i * L + l] = a[i].y;
            bx_[i * L + l] = b[i].x;
            by_[i * L + l] = b[i].y;
        }
    }

    // three DP rows and two rows of substitution costs, each width x L
    rows_.resize(5 * width * L);
    float* before = rows_.data();
    float* previous = before + width * L;
    float* current = previous + width * L;
    float* previous_cost = current + width * L;
    float* current_cost = previous_cost + width * L;
    for (std::size_t j = 0; j <= n; ++j) {
        for (std::size_t l = 0; l < L; ++l) {
            previous[j * L + l] = static_cast<float>(j);
            previous_cost[j * L + l] = 1.0f;
        }
    }

    for (std::size_t i = 1; i <= n; ++i) {
        const float* ax = &ax_[(i - 1) * L];
        const float* ay = &ay_[(i - 1) * L];
        for (std::size_t l = 0; l < L; ++l) {
            current[l] = static_cast<float>(i);
            current_cost[l] = 1.0f;
        }
        for (std::size_t j = 1; j <= n; ++j) {
            const float* bx = &bx_[(j - 1) * L];
            const float* by = &by_[(j - 1) * L];
            const float* up = &previous[j * L];
            const float* diagonal = &previous[(j - 1) * L];
            const float* left = &current[(j - 1) * L];
            const float* far = &before[(j - 2 < width ? j - 2 : 0) * L];
            const float* cost_left = &current_cost[(j - 1) * L];
            const float* cost_up = &previous_cost[j * L];
            float* cell = &current[j * L];
            float* cost_out = &current_cost[j * L];
            // four lanes per SSE vector; the swap test is a mask, not a branch
            const float swap_blocked = i > 1 && j > 1 ? 0.0f : 1.0f;
            for (std::size_t g = 0; g < L; g += 4) {
                const V4 cost = (vabs(load(ax + g) - load(bx + g)) + vabs(load(ay + g) - load(by + g))) / kGridTiles;
                const V4 d = vmin(vmin(load(up + g) + 1.0f, load(left + g) + 1.0f), load(diagonal + g) + cost);
                // a[i-1] == b[j-2] and a[i-2] == b[j-1] are zero costs of the neighbours
                const V4 swapped = load(far + g) + cost;
                const M4 swap = (load(cost_left + g) + load(cost_up + g) + swap_blocked == 0.0f) & (swapped < d);
                store(cell + g, swap ? swapped : d);
                store(cost_out + g, cost);
            }
        }
        std::swap(before, previous);
        std::swap(previous, current);
        std::swap(previous_cost, current_cost);
    }
    for (std::size_t l = 0; l < count; ++l) out[l] = previous[n * L + l];
}

}  // namespace stepstone::evo
