#include "kb/signature_scan.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

#include "core/assert.hpp"
#include "kb/detail/simd.hpp"
#include "kb/distance.hpp"

#if defined(__x86_64__)
#include <immintrin.h>
#endif

namespace stepstone::kb {

namespace {

// segments compared at once by the counts' stage (one AVX2 register of bytes)
constexpr std::size_t kGroup = 32;
// rows of a block of the other channels' bound
constexpr std::size_t kBlockRows = 4;
static_assert((kBlockRows & (kBlockRows - 1)) == 0, "check() multiplies by 1 / kBlockRows");
// a block sum is rounded to float from a double sum of <= kBlockRows floats:
// it lies within 2^-24 x 4 M (+ 2^-50 M) of the exact sum, M the largest
// |value|; a difference of two, within 2^-20.9 M: the pad is 2^-19 M
constexpr double kPadPerMagnitude = 0x1p-19;
// the bound of stage 3 is scaled down by this much before it is compared:
// the double sums of both it and squared_distance() are exact to ~2^-43
// (relative) for any dim below 2^10
constexpr double kBoundScale = 1.0 - 0x1p-30;
// block sums are used while their floats and squares cannot overflow
constexpr double kMaxMagnitude = 1e30;

bool is_binary(float v) { return v == 0.0f || v == 1.0f; }

// the largest integer below x, clamped to [-1, 255]
int below(double x) {
    if (!(x > 0.0)) return -1;
    if (x > 255.0) return 255;
    return static_cast<int>(std::ceil(x)) - 1;
}

// the largest integer at most x, clamped to [-1, 255]
int at_most(double x) {
    if (!(x >= 0.0)) return -1;
    if (x >= 255.0) return 255;
    return static_cast<int>(std::floor(x));
}

// stage 3's squared gaps, max(0, |q[i] - s[i]| - pad)^2 of the n block sums, into out[i]
void gap_squares_generic(const float* q, const float* s, double pad, std::size_t n, double* out) {
    for (std::size_t i = 0; i < n; ++i) {
        const double gap =
            std::max(0.0, std::fabs(static_cast<double>(q[i]) - static_cast<double>(s[i])) - pad);
        out[i] = gap * gap;
    }
}

#if defined(__x86_64__)
// gap_squares_generic four at a time: the same operations (max_pd(x, 0) is x > 0 ? x : 0, as
// std::max(0.0, x); the absolute value clears the sign bit)
[[gnu::target("avx2")]] void gap_squares_avx2(const float* q, const float* s, double pad, std::size_t n,
                                              double* out) {
    const __m256d sign = _mm256_set1_pd(-0.0);
    const __m256d pads = _mm256_set1_pd(pad);
    const __m256d zero = _mm256_setzero_pd();
    std::size_t i = 0;
    for (; i + 4 <= n; i += 4) {
        const __m256d d =
            _mm256_sub_pd(_mm256_cvtps_pd(_mm_loadu_ps(q + i)), _mm256_cvtps_pd(_mm_loadu_ps(s + i)));
        const __m256d gap = _mm256_max_pd(_mm256_sub_pd(_mm256_andnot_pd(sign, d), pads), zero);
        _mm256_storeu_pd(out + i, _mm256_mul_pd(gap, gap));
    }
    gap_squares_generic(q + i, s + i, pad, n - i, out + i);
}
#else
void gap_squares_avx2(const float* q, const float* s, double pad, std::size_t n, double* out) {
    gap_squares_generic(q, s, pad, n, out);
}
#endif

// block sums whose squared gaps check() takes from the stack; more take the plain loop
constexpr std::size_t kMaxBlockSums = 512;

}  // namespace

// one scan's state: the query, the limits and the best segment so far
struct SignatureScan::Scan {
    const Query& q;
    const float* values;
    double radius_sq;
    double worst;
    bool found = false;
    std::size_t best = 0;
    double best_d2 = 0.0;
    int max_count_gap = 255;  // stage 1 passes a segment whose L1 is at most this

    // a segment with lower bound `lb` can still be the answer
    bool admits(double lb) const { return lb < radius_sq && (found ? lb < best_d2 : lb <= worst); }
    void update_count_gap() {
        max_count_gap = std::min(below(radius_sq), found ? below(best_d2) : at_most(worst));
    }
};

std::vector<std::size_t> SignatureScan::binary_channels(std::span<const float> values, std::size_t width,
                                                        std::size_t channels) {
    std::vector<bool> binary(channels, true);
    const std::size_t dim = width * channels;
    for (std::size_t k = 0; k + dim <= values.size(); k += dim)
        for (std::size_t i = 0; i < dim; ++i)
            if (!is_binary(values[k + i])) binary[i % channels] = false;
    std::vector<std::size_t> out;
    for (std::size_t c = 0; c < channels; ++c)
        if (binary[c]) out.push_back(c);
    return out;
}

SignatureScan::SignatureScan(std::size_t width, std::size_t channels, std::vector<std::size_t> binary)
    : width_(width), channels_(channels), binary_(std::move(binary)) {
    STEPSTONE_ASSERT(width >= 1 && channels >= 1);
    std::vector<bool> is(channels, false);
    for (const std::size_t c : binary_) {
        STEPSTONE_ASSERT(c < channels && !is[c]);
        is[c] = true;
    }
    for (std::size_t c = 0; c < channels; ++c)
        if (!is[c]) other_.push_back(c);
    words_ = (width * binary_.size() + 63) / 64;
    blocks_ = (width + kBlockRows - 1) / kBlockRows;
    counts_on_ = !binary_.empty() && width * binary_.size() <= 255;
}

void SignatureScan::add(const float* segment) {
    const std::size_t nb = binary_.size();
    if (counts_on_ && size_ % kGroup == 0) counts_.resize(counts_.size() + nb * kGroup, 0);
    const std::size_t group = size_ / kGroup;
    const std::size_t lane = size_ % kGroup;
    const std::size_t first_word = bits_.size();
    bits_.resize(bits_.size() + words_, 0);
    for (std::size_t j = 0; j < nb; ++j) {
        std::size_t ones = 0;
        for (std::size_t r = 0; r < width_; ++r) {
            const float v = segment[r * channels_ + binary_[j]];
            STEPSTONE_ASSERT(is_binary(v));
            if (v == 1.0f) {
                const std::size_t bit = r * nb + j;
                bits_[first_word + bit / 64] |= std::uint64_t{1} << (bit % 64);
                ++ones;
            }
        }
        if (counts_on_) counts_[(group * nb + j) * kGroup + lane] = static_cast<std::uint8_t>(ones);
    }
    for (std::size_t b = 0; b < blocks_; ++b) {
        for (const std::size_t c : other_) {
            double sum = 0.0;
            for (std::size_t r = b * kBlockRows; r < std::min(width_, (b + 1) * kBlockRows); ++r) {
                const float v = segment[r * channels_ + c];
                sum += static_cast<double>(v);
                max_abs_ = std::max(max_abs_, static_cast<double>(std::fabs(v)));
            }
            sums_.push_back(static_cast<float>(sum));
        }
    }
    ++size_;
}

double SignatureScan::bytes_per_segment() const {
    return static_cast<double>((counts_on_ ? binary_.size() : 0) + words_ * sizeof(std::uint64_t) +
                               blocks_ * other_.size() * sizeof(float));
}

SignatureScan::Query SignatureScan::Queries::operator[](std::size_t i) const {
    Query q;
    q.values = values_ + i * dim_;
    q.counts_usable = counts_usable_[i] != 0;
    q.counts = counts_.data() + i * nb_;
    q.bits = bits_.data() + i * words_;
    q.mask = mask_.data() + i * words_;
    q.sums = sums_.data() + i * sums_per_;
    q.sums_usable = sums_usable_[i] != 0;
    q.pad = pad_[i];
    return q;
}

namespace {

// max(0, |values[k]|...) as a left fold of std::max over k, which skips NaN (std::max(m, NaN)
// is m) and is otherwise the largest magnitude: the same whatever the order, so eight running
// maxima, which the compiler keeps in one vector, give the fold's value without its chain of
// dependent steps
float largest_magnitude(const float* values, std::size_t count) {
    constexpr std::size_t kRunning = 8;
    float running[kRunning] = {};
    std::size_t k = 0;
    for (; k + kRunning <= count; k += kRunning) {
        for (std::size_t u = 0; u < kRunning; ++u)
            running[u] = std::max(running[u], std::fabs(values[k + u]));
    }
    for (; k < count; ++k) running[0] = std::max(running[0], std::fabs(values[k]));
    float largest = 0.0f;
    for (const float m : running) largest = std::max(largest, m);
    return largest;
}

}  // namespace

SignatureScan::Queries SignatureScan::prepare(const float* queries, std::size_t count) const {
    Queries out;
    const std::size_t nb = binary_.size();
    out.count_ = count;
    out.dim_ = dim();
    out.nb_ = nb;
    out.words_ = words_;
    out.sums_per_ = blocks_ * other_.size();
    out.values_ = queries;
    out.counts_.assign(count * nb, 0);
    out.counts_usable_.assign(count, counts_on_ ? 1 : 0);
    out.sums_usable_.assign(count, 0);
    out.bits_.assign(count * words_, 0);
    out.mask_.assign(count * words_, 0);
    out.sums_.assign(count * out.sums_per_, 0.0f);
    out.pad_.assign(count, 0.0);
    const std::size_t no = other_.size();
    std::vector<double> block(blocks_ * no);
    for (std::size_t i = 0; i < count; ++i) {
        const float* query = queries + i * dim();
        std::uint8_t* counts = out.counts_.data() + i * nb;
        std::uint64_t* bits = out.bits_.data() + i * words_;
        std::uint64_t* mask = out.mask_.data() + i * words_;
        // the largest magnitude of all values (a value of a binary channel
        // adds at most 1 to the pad's scale)
        float max_abs = largest_magnitude(query, dim());
        bool binary = true;
        std::fill(block.begin(), block.end(), 0.0);
        // bit r * nb + j of the bits and the mask, gathered a 64-bit word at a time in registers
        // (an or into memory a bit would chain every bit to the last through the store)
        std::uint64_t word_bits = 0;
        std::uint64_t word_mask = 0;
        std::size_t bit = 0;
        for (std::size_t r = 0; r < width_; ++r) {
            const float* row = query + r * channels_;
            for (std::size_t j = 0; j < nb; ++j, ++bit) {
                const float v = row[binary_[j]];
                const bool one = v == 1.0f;
                const bool valid = one || v == 0.0f;
                binary = binary && valid;
                word_bits |= std::uint64_t{one} << (bit % 64);
                word_mask |= std::uint64_t{valid} << (bit % 64);
                if (bit % 64 == 63) {
                    bits[bit / 64] = word_bits;
                    mask[bit / 64] = word_mask;
                    word_bits = 0;
                    word_mask = 0;
                }
                // at most width_ <= 255 ones when counts are used
                counts[j] = static_cast<std::uint8_t>(counts[j] + one);
            }
            double* row_block = block.data() + r / kBlockRows * no;
            for (std::size_t o = 0; o < no; ++o) row_block[o] += static_cast<double>(row[other_[o]]);
        }
        if (bit % 64 != 0) {
            bits[bit / 64] = word_bits;
            mask[bit / 64] = word_mask;
        }
        float* sums = out.sums_.data() + i * out.sums_per_;
        for (std::size_t k = 0; k < block.size(); ++k) sums[k] = static_cast<float>(block[k]);
        const double magnitude = std::max(max_abs_, static_cast<double>(max_abs));
        if (!binary) out.counts_usable_[i] = 0;
        out.sums_usable_[i] = no > 0 && magnitude < kMaxMagnitude;
        out.pad_[i] = kPadPerMagnitude * magnitude;
    }
    return out;
}

// stages 2 to 4 for segment k (stage 1 passed or skipped); true when it
// became the best so far
template <bool kAvx2>
[[gnu::always_inline]] inline bool SignatureScan::check(Scan& s, std::size_t k) const {
    const Query& q = s.q;
    const std::uint64_t* bits = bits_.data() + k * words_;
    std::size_t h = 0;
    for (std::size_t w = 0; w < words_; ++w)
        h += static_cast<std::size_t>(std::popcount((q.bits[w] ^ bits[w]) & q.mask[w]));
    const double hamming = static_cast<double>(h);
    if (!s.admits(hamming)) return false;
    if (q.sums_usable) {
        const std::size_t no = other_.size();
        const std::size_t count = blocks_ * no;
        const float* sums = sums_.data() + k * count;
        // the squared gaps first, in vectors where they can be; then each block's sum in order
        double squares[kMaxBlockSums];
        const bool stacked = count <= kMaxBlockSums;
        if (stacked) {
            if constexpr (kAvx2) {
                gap_squares_avx2(q.sums, sums, q.pad, count, squares);
            } else {
                gap_squares_generic(q.sums, sums, q.pad, count, squares);
            }
        }
        double cs = 0.0;
        for (std::size_t b = 0, i = 0; b < blocks_; ++b) {
            const std::size_t rows = std::min(width_, (b + 1) * kBlockRows) - b * kBlockRows;
            double block = 0.0;
            for (std::size_t o = 0; o < no; ++o, ++i) {
                if (stacked) {
                    block += squares[i];
                    continue;
                }
                double square = 0.0;
                gap_squares_generic(q.sums + i, sums + i, q.pad, 1, &square);
                block += square;
            }
            // a full block's quotient by kBlockRows, a power of two, is its product by the
            // inverse, exactly (one rounding of the same real): a multiply, not a division, in
            // the chain of sums
            cs += rows == kBlockRows ? block * (1.0 / kBlockRows) : block / static_cast<double>(rows);
        }
        if (!s.admits((hamming + cs) * kBoundScale)) return false;
    }
    const std::size_t n = dim();
    const float* segment = s.values + k * n;
    const double bound = s.found ? s.best_d2 : std::min(s.worst, s.radius_sq);
    const double d2 = squared_distance_up_to(q.values, segment, n, bound);
    if (!(d2 < s.radius_sq && (s.found ? d2 < s.best_d2 : d2 <= s.worst))) return false;
    s.found = true;
    s.best = k;
    s.best_d2 = d2;
    s.update_count_gap();
    return true;
}

void SignatureScan::scan_generic(Scan& s) const {
    const std::size_t nb = binary_.size();
    std::uint8_t gaps[kGroup];
    for (std::size_t base = 0; base < size_; base += kGroup) {
        if (s.max_count_gap < 0) return;
        const std::size_t lanes = std::min(kGroup, size_ - base);
        const std::uint8_t* group = counts_.data() + base / kGroup * nb * kGroup;
        for (std::size_t lane = 0; lane < lanes; ++lane) {
            unsigned gap = 0;
            for (std::size_t j = 0; j < nb; ++j) {
                const int d = static_cast<int>(group[j * kGroup + lane]) - static_cast<int>(s.q.counts[j]);
                gap += static_cast<unsigned>(d < 0 ? -d : d);
            }
            gaps[lane] = static_cast<std::uint8_t>(gap);
        }
        for (std::size_t lane = 0; lane < lanes; ++lane)
            if (gaps[lane] <= s.max_count_gap) check<false>(s, base + lane);
    }
}

#if defined(__x86_64__)
[[gnu::target("avx2,popcnt")]] void SignatureScan::scan_avx2(Scan& s) const {
    const std::size_t nb = binary_.size();
    alignas(32) std::uint8_t gaps[kGroup];
    for (std::size_t base = 0; base < size_; base += kGroup) {
        if (s.max_count_gap < 0) return;
        const std::size_t lanes = std::min(kGroup, size_ - base);
        const std::uint8_t* group = counts_.data() + base / kGroup * nb * kGroup;
        __m256i sum = _mm256_setzero_si256();
        for (std::size_t j = 0; j < nb; ++j) {
            const __m256i c = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(group + j * kGroup));
            const __m256i q = _mm256_set1_epi8(static_cast<char>(s.q.counts[j]));
            // |c - q| in bytes; the total stays <= 255 (counts_on_)
            sum = _mm256_add_epi8(sum, _mm256_or_si256(_mm256_subs_epu8(c, q), _mm256_subs_epu8(q, c)));
        }
        const __m256i limit = _mm256_set1_epi8(static_cast<char>(s.max_count_gap));
        const __m256i pass = _mm256_cmpeq_epi8(_mm256_min_epu8(sum, limit), sum);
        auto bits = static_cast<std::uint32_t>(_mm256_movemask_epi8(pass));
        if (lanes < kGroup) bits &= (std::uint32_t{1} << lanes) - 1;
        if (bits == 0) continue;
        _mm256_store_si256(reinterpret_cast<__m256i*>(gaps), sum);
        while (bits != 0) {
            const auto lane = static_cast<std::size_t>(std::countr_zero(bits));
            bits &= bits - 1;
            // the limit may have shrunk since the comparison
            if (gaps[lane] <= s.max_count_gap) check<true>(s, base + lane);
        }
    }
}
#else
void SignatureScan::scan_avx2(Scan& s) const { scan_generic(s); }
#endif

std::optional<Neighbour> SignatureScan::nearest(const Query& query, const float* values, double radius_sq,
                                                double worst) const {
    Scan s{query, values, radius_sq, worst};
    s.update_count_gap();
    if (counts_on_ && query.counts_usable) {
        if (detail::use_avx2())
            scan_avx2(s);
        else
            scan_generic(s);
    } else {
        if (detail::use_avx2()) {
            for (std::size_t k = 0; k < size_; ++k) check<true>(s, k);
        } else {
            for (std::size_t k = 0; k < size_; ++k) check<false>(s, k);
        }
    }
    if (!s.found) return std::nullopt;
    return Neighbour{s.best, s.best_d2};
}

}  // namespace stepstone::kb
