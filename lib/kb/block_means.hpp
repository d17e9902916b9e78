#pragma once

#include <cstddef>

namespace stepstone::kb {

/// Lower-bound points of segments: the rows of a segment (`width` rows of
/// `channels` values, row-major) are cut into `blocks` contiguous row blocks,
/// block b holding rows [b * width / blocks, (b + 1) * width / blocks); the
/// point has one coordinate per block and channel (index b * channels + c):
/// the sum of the channel's values over the block's rows divided by the
/// square root of the block's row count, i.e. their mean times sqrt(rows).
///
/// For any two segments a and b, ||P(a) - P(b)|| <= ||a - b||: within one
/// block and channel, the sum of the r squared differences is at least r times
/// the squared difference of the means (Cauchy-Schwarz), and the blocks and
/// channels partition the values. More blocks give a tighter bound in more
/// dimensions; blocks = width gives the segment itself.
class BlockMeans {
public:
    /// Points for segments of `width` rows of `channels` values, with
    /// min(blocks, width) blocks (at least one).
    BlockMeans(std::size_t width, std::size_t channels, std::size_t blocks);

    std::size_t blocks() const { return blocks_; }
    /// Coordinates per point (blocks() x channels).
    std::size_t dim() const { return blocks_ * channels_; }

    /// Writes the point of `segment` to out[0, dim()), computed in double;
    /// returns the largest absolute value of the segment: NaN if a value is
    /// NaN, else infinity if one is infinite (the point is then meaningless).
    double point(const float* segment, double* out) const;

private:
    std::size_t width_;
    std::size_t channels_;
    std::size_t blocks_;
};

/// Squared Euclidean distance of two points of `n` doubles (four partial
/// sums, so it vectorises; callers pad for its rounding).
double squared_gap(const double* a, const double* b, std::size_t n);

/// Squared Euclidean distance of two points of `n` floats in single
/// precision (eight partial sums). With finite squares it is within a
/// relative (n + 2) x 2^-24 of the exact value, plus 1e-30 for underflow.
float squared_gap(const float* a, const float* b, std::size_t n);

}  // namespace stepstone::kb
