#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "kb/segment_index.hpp"

namespace stepstone::kb {

/// An exact nearest-segment scan made cheap by the channels that hold only 0
/// and 1 (in the paper's behaviour, 9 of the 15: light sensors, bumpers and
/// the carrying flag).
///
/// For values a, b in {0, 1}, (a - b)^2 is a XOR b, so the binary channels of
/// two segments add exactly their Hamming distance H to the squared distance,
/// and at least the difference of their numbers of ones, channel by channel.
/// A scan takes the segments in order and drops one as soon as a lower bound
/// proves it cannot be the answer, each stage dearer and tighter than the one
/// before:
///  1. L1 distance of the numbers of ones per binary channel, 32 segments at
///     a time in bytes (AVX2 where the CPU has it);
///  2. H, from the binary values packed as bits;
///  3. H plus the block-means bound of the other channels (row blocks of 4:
///     (difference of the block sums)^2 / rows, by Cauchy-Schwarz), padded
///     for the rounding of the float block sums;
///  4. squared_distance_up_to() itself.
/// No bound exceeds the squared_distance() the KB computes (H is a sum of
/// ones, which the double lanes add exactly; stage 3 is padded and scaled
/// down), so every answer is a linear scan's, ties going to the lowest index.
///
/// A query whose binary channels hold other values than 0 and 1 skips the
/// bounds of those channels; the answers stay exact, only slower.
class SignatureScan {
public:
    /// The channels whose values are all exactly 0 or 1 (-0.0 counts as 0) in
    /// the segments of `values` (width x channels values each), in order.
    static std::vector<std::size_t> binary_channels(std::span<const float> values, std::size_t width,
                                                    std::size_t channels);

    /// An empty scan for segments of `width` rows of `channels` values whose
    /// channels `binary` (increasing, each < channels) hold only 0 and 1.
    SignatureScan(std::size_t width, std::size_t channels, std::vector<std::size_t> binary);

    /// Adds one segment (index size()); its binary channels must hold only 0 and 1.
    void add(const float* segment);
    /// Number of segments added.
    std::size_t size() const { return size_; }
    /// Values per segment.
    std::size_t dim() const { return width_ * channels_; }
    /// Bytes held per segment (counts, bits and block sums).
    double bytes_per_segment() const;

    /// A query's signature (a view into its Queries).
    struct Query {
        const float* values = nullptr;
        bool counts_usable = false;            // every binary channel of the query is 0/1
        const std::uint8_t* counts = nullptr;  // ones per binary channel
        const std::uint64_t* bits = nullptr;   // binary values (0 where not 0/1)
        const std::uint64_t* mask = nullptr;   // bits whose query value is 0/1
        const float* sums = nullptr;           // block sums of the other channels
        bool sums_usable = false;
        double pad = 0.0;  // rounding allowance of a block-sum difference
    };
    /// The signatures of a batch of queries, computed once for any number of scans.
    class Queries {
    public:
        std::size_t size() const { return count_; }
        Query operator[](std::size_t i) const;

    private:
        friend class SignatureScan;
        std::size_t count_ = 0;
        std::size_t dim_ = 0, nb_ = 0, words_ = 0, sums_per_ = 0;
        const float* values_ = nullptr;
        std::vector<std::uint8_t> counts_, counts_usable_, sums_usable_;
        std::vector<std::uint64_t> bits_, mask_;
        std::vector<float> sums_;
        std::vector<double> pad_;
    };
    /// The signatures of the `count` queries at `queries` (dim() finite
    /// values each, kept by pointer).
    Queries prepare(const float* queries, std::size_t count) const;

    /// The nearest segment k (values at values + k * dim()) with squared
    /// distance < radius_sq and <= `worst`, ties going to the lowest k; nullopt
    /// when there is none. `worst` lets a caller that already holds a match
    /// (from another scan) skip what cannot equal or beat it.
    std::optional<Neighbour> nearest(const Query& query, const float* values, double radius_sq,
                                     double worst) const;

private:
    struct Scan;
    void scan_generic(Scan& scan) const;
    void scan_avx2(Scan& scan) const;
    template <bool kAvx2>
    bool check(Scan& scan, std::size_t k) const;

    std::size_t width_;
    std::size_t channels_;
    std::vector<std::size_t> binary_;  // binary channels
    std::vector<std::size_t> other_;   // the other channels
    std::size_t words_ = 0;            // 64-bit words of bits per segment
    std::size_t blocks_ = 0;           // row blocks of the block sums
    bool counts_on_ = false;           // counts fit a byte and their L1 too
    std::size_t size_ = 0;
    double max_abs_ = 0.0;              // largest |value| of the other channels
    std::vector<std::uint8_t> counts_;  // groups of 32 segments: [group][binary channel][lane]
    std::vector<std::uint64_t> bits_;   // words_ per segment
    std::vector<float> sums_;           // blocks_ x other_ per segment
};

}  // namespace stepstone::kb
