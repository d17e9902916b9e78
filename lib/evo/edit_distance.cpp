#include "evo/edit_distance.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>

#include "core/assert.hpp"
#include "core/cpu.hpp"

#if defined(__x86_64__) || defined(__i386__)
#define STEPSTONE_EVO_HAVE_AVX2_KERNEL 1
#include <immintrin.h>
#endif

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

namespace {

// The batch's dynamic programme on lane-interleaved cells (ax..by, n x
// kLanes floats each): the portable version in four-lane SSE vectors.
void batch_portable(const float* ax_all, const float* ay_all, const float* bx_all, const float* by_all,
                    std::size_t n, float* rows, float* out, std::size_t count) {
    constexpr std::size_t L = kLanes;
    static_assert(L % 4 == 0);
    const std::size_t width = n + 1;

    // three DP rows and two rows of substitution costs, each width x L
    float* before = rows;
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
        const float* ax = &ax_all[(i - 1) * L];
        const float* ay = &ay_all[(i - 1) * L];
        for (std::size_t l = 0; l < L; ++l) {
            current[l] = static_cast<float>(i);
            current_cost[l] = 1.0f;
        }
        for (std::size_t j = 1; j <= n; ++j) {
            const float* bx = &bx_all[(j - 1) * L];
            const float* by = &by_all[(j - 1) * L];
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

#ifdef STEPSTONE_EVO_HAVE_AVX2_KERNEL
// The same programme in AVX2: the 16 lanes are two vectors of 8 floats. One
// self-contained function of intrinsics (no helper takes or returns a
// vector), so nothing with a 32-byte vector crosses into baseline code.
//
// Every lane does the IEEE operations of the portable version: the same
// costs (|dx| + |dy|) / 12 and the same candidate sums. Only the order of
// the minimum changes, D = min(left + 1, min(min(up + 1, diagonal + cost),
// swap)), which keeps left + 1 alone on the dependency chain along the row;
// the values are never NaN nor -0, so the minimum of the same candidates is
// the same float in any order.
//
// Each row has one more slot in front, column -1, held at +infinity, and
// the row before row 1 is all +infinity: the transposition then needs no
// test of i > 1 or j > 1, its candidate is +infinity there. A row of
// equality masks (a[i-1] == b[j-1], as cost == 0) feeds the next row's
// transposition test.
[[gnu::target("avx2")]] void batch_avx2(const float* ax_all, const float* ay_all, const float* bx_all,
                                        const float* by_all, std::size_t n, float* rows, float* out,
                                        std::size_t count) {
    constexpr std::size_t L = kLanes;
    static_assert(L == 16);
    const std::size_t slots = (n + 2) * L;  // columns -1 .. n

    float* before = rows;
    float* previous = before + slots;
    float* current = previous + slots;
    float* previous_equal = current + slots;
    float* current_equal = previous_equal + slots;

    const __m256 infinity = _mm256_set1_ps(__builtin_inff());
    const __m256 one = _mm256_set1_ps(1.0f);
    const __m256 tiles = _mm256_set1_ps(kGridTiles);
    const __m256 sign = _mm256_set1_ps(-0.0f);
    const __m256 zero = _mm256_setzero_ps();

    // row -1: +infinity; row 0: D[0][j] = j; no equal cells above row 1
    for (std::size_t s = 0; s < slots; s += 8) {
        _mm256_storeu_ps(before + s, infinity);
        _mm256_storeu_ps(previous_equal + s, zero);
    }
    _mm256_storeu_ps(previous, infinity);
    _mm256_storeu_ps(previous + 8, infinity);
    for (std::size_t j = 0; j <= n; ++j) {
        const __m256 column = _mm256_set1_ps(static_cast<float>(j));
        _mm256_storeu_ps(previous + (j + 1) * L, column);
        _mm256_storeu_ps(previous + (j + 1) * L + 8, column);
    }

    for (std::size_t i = 1; i <= n; ++i) {
        const float* ax = ax_all + (i - 1) * L;
        const float* ay = ay_all + (i - 1) * L;
        const __m256 ax0 = _mm256_loadu_ps(ax);
        const __m256 ax1 = _mm256_loadu_ps(ax + 8);
        const __m256 ay0 = _mm256_loadu_ps(ay);
        const __m256 ay1 = _mm256_loadu_ps(ay + 8);

        // columns -1 and 0 of row i
        _mm256_storeu_ps(current, infinity);
        _mm256_storeu_ps(current + 8, infinity);
        __m256 left0 = _mm256_set1_ps(static_cast<float>(i));
        __m256 left1 = left0;
        _mm256_storeu_ps(current + L, left0);
        _mm256_storeu_ps(current + L + 8, left1);
        __m256 diagonal0 = _mm256_loadu_ps(previous + L);
        __m256 diagonal1 = _mm256_loadu_ps(previous + L + 8);
        __m256 equal_left0 = zero;
        __m256 equal_left1 = zero;

        for (std::size_t j = 1; j <= n; ++j) {
            const float* bx = bx_all + (j - 1) * L;
            const float* by = by_all + (j - 1) * L;
            const std::size_t at = (j + 1) * L;   // column j
            const std::size_t far = (j - 1) * L;  // column j - 2

            // lanes 0..7
            const __m256 manhattan0 =
                _mm256_add_ps(_mm256_andnot_ps(sign, _mm256_sub_ps(ax0, _mm256_loadu_ps(bx))),
                              _mm256_andnot_ps(sign, _mm256_sub_ps(ay0, _mm256_loadu_ps(by))));
            const __m256 cost0 = _mm256_div_ps(manhattan0, tiles);
            const __m256 equal0 = _mm256_cmp_ps(manhattan0, zero, _CMP_EQ_OQ);
            const __m256 up0 = _mm256_loadu_ps(previous + at);
            const __m256 swap0 = _mm256_and_ps(equal_left0, _mm256_loadu_ps(previous_equal + at));
            const __m256 swapped0 =
                _mm256_blendv_ps(infinity, _mm256_add_ps(_mm256_loadu_ps(before + far), cost0), swap0);
            const __m256 rest0 = _mm256_min_ps(
                _mm256_min_ps(_mm256_add_ps(up0, one), _mm256_add_ps(diagonal0, cost0)), swapped0);
            left0 = _mm256_min_ps(_mm256_add_ps(left0, one), rest0);
            _mm256_storeu_ps(current + at, left0);
            _mm256_storeu_ps(current_equal + at, equal0);
            diagonal0 = up0;
            equal_left0 = equal0;

            // lanes 8..15
            const __m256 manhattan1 =
                _mm256_add_ps(_mm256_andnot_ps(sign, _mm256_sub_ps(ax1, _mm256_loadu_ps(bx + 8))),
                              _mm256_andnot_ps(sign, _mm256_sub_ps(ay1, _mm256_loadu_ps(by + 8))));
            const __m256 cost1 = _mm256_div_ps(manhattan1, tiles);
            const __m256 equal1 = _mm256_cmp_ps(manhattan1, zero, _CMP_EQ_OQ);
            const __m256 up1 = _mm256_loadu_ps(previous + at + 8);
            const __m256 swap1 = _mm256_and_ps(equal_left1, _mm256_loadu_ps(previous_equal + at + 8));
            const __m256 swapped1 =
                _mm256_blendv_ps(infinity, _mm256_add_ps(_mm256_loadu_ps(before + far + 8), cost1), swap1);
            const __m256 rest1 = _mm256_min_ps(
                _mm256_min_ps(_mm256_add_ps(up1, one), _mm256_add_ps(diagonal1, cost1)), swapped1);
            left1 = _mm256_min_ps(_mm256_add_ps(left1, one), rest1);
            _mm256_storeu_ps(current + at + 8, left1);
            _mm256_storeu_ps(current_equal + at + 8, equal1);
            diagonal1 = up1;
            equal_left1 = equal1;
        }
        float* const oldest = before;
        before = previous;
        previous = current;
        current = oldest;
        float* const old_equal = previous_equal;
        previous_equal = current_equal;
        current_equal = old_equal;
    }
    for (std::size_t l = 0; l < count; ++l) out[l] = previous[(n + 1) * L + l];
}
#endif

}  // namespace

EditDistanceBatch::EditDistanceBatch(Simd simd) : avx2_(simd == Simd::automatic && avx2_kernels_allowed()) {}

void EditDistanceBatch::run(std::span<const GridCell* const> first, std::span<const GridCell* const> second,
                            std::size_t length, float* out) {
    constexpr std::size_t L = kLanes;
    const std::size_t count = first.size();
    STEPSTONE_ASSERT(count == second.size() && count >= 1 && count <= L);
    const std::size_t n = length;

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

    // five rows of L lanes each: three of distances, two of costs or equalities
    rows_.resize(5 * (n + 2) * L);
#ifdef STEPSTONE_EVO_HAVE_AVX2_KERNEL
    if (avx2_) return batch_avx2(ax_.data(), ay_.data(), bx_.data(), by_.data(), n, rows_.data(), out, count);
#endif
    batch_portable(ax_.data(), ay_.data(), bx_.data(), by_.data(), n, rows_.data(), out, count);
}

}  // namespace stepstone::evo
