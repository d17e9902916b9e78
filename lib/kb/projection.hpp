#pragma once

#include <cstddef>
#include <vector>

namespace stepstone::kb {

/// A linear map with orthonormal rows from the points of a BlockMeans (`in`
/// coordinates) to `out` <= `in` coordinates. Rows orthonormal make it a
/// contraction: ||P(x) - P(y)|| <= ||x - y||, so a projected block-means point
/// still bounds the segment distance from below (up to the rounding that
/// SegmentIndex pads for; construction checks orthonormality to 1e-12).
class Projection {
public:
    /// The channel means of BlockMeans(width, channels, blocks) points, scaled
    /// by sqrt(width): out coordinate c = sum over blocks b of
    /// sqrt(rows_b / width) x in[b * channels + c].
    static Projection channel_means(std::size_t width, std::size_t channels, std::size_t blocks);
    /// The `out` leading principal directions of `count` points of `in` floats
    /// (a deterministic sample of at most 4096 of them), from Eigen's
    /// self-adjoint eigen-decomposition of their covariance; out <= in,
    /// count >= 2.
    /// Returns channel_means-like fallback `fallback` when the directions are not
    /// orthonormal to 1e-12 after re-orthonormalisation.
    static Projection principal(const float* points, std::size_t count, std::size_t in, std::size_t out,
                                const Projection& fallback);

    std::size_t in_dim() const { return in_; }
    std::size_t out_dim() const { return out_; }
    /// out[0, out_dim()) = the projection of in[0, in_dim()), in double.
    void apply(const double* in, double* out) const;
    void apply(const float* in, double* out) const;

    /// Largest |R R^T - I| entry over the rows R.
    double orthonormality_error() const;

private:
    Projection(std::size_t in, std::size_t out, std::vector<double> rows);

    std::size_t in_ = 0;
    std::size_t out_ = 0;
    std::vector<double> rows_;     // out_ rows of in_ values
    std::vector<double> columns_;  // the same transposed: in_ rows of out_ values padded to a multiple of 4
};

}  // namespace stepstone::kb
