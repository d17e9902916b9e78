#include "kb/projection.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>
#include <utility>

#include <Eigen/Eigenvalues>

#include "core/assert.hpp"
#include "kb/detail/simd.hpp"

namespace stepstone::kb {

namespace {

constexpr std::size_t kMaxSample = 4096;
constexpr double kOrthonormalTolerance = 1e-12;

// modified Gram-Schmidt over the rows, twice; a row that vanishes is left 0
void orthonormalise(std::vector<double>& rows, std::size_t count, std::size_t n) {
    for (int pass = 0; pass < 2; ++pass) {
        for (std::size_t i = 0; i < count; ++i) {
            double* r = rows.data() + i * n;
            for (std::size_t j = 0; j < i; ++j) {
                const double* u = rows.data() + j * n;
                const double dot = std::inner_product(r, r + n, u, 0.0);
                for (std::size_t k = 0; k < n; ++k) r[k] -= dot * u[k];
            }
            const double norm = std::sqrt(std::inner_product(r, r + n, r, 0.0));
            for (std::size_t k = 0; k < n; ++k) r[k] = norm > 0 ? r[k] / norm : 0.0;
        }
    }
}

// four doubles (GCC and Clang vector extension)
typedef double Quad __attribute__((vector_size(4 * sizeof(double))));

// outputs [4 q0, 4 (q0 + Q)) of the projection of `in`: output r is the dot
// product of row r and `in` as four partial sums, sum j over the terms
// k = j (mod 4) in increasing k, then (s0 + s1) + (s2 + s3). `columns` holds
// the rows transposed (in_dim rows of `stride` doubles, zero past the last
// output), so that four outputs are one vector; the Q x 4 partial sums stay
// in registers for Q <= 3
template <std::size_t Q, class T>
[[gnu::always_inline]] inline void project_quads(const double* columns, std::size_t stride, std::size_t in_dim,
                                                 std::size_t q0, const T* in, double* out, std::size_t out_dim) {
    Quad s[4][Q] = {};
    const double* col = columns + q0 * 4;
    std::size_t k = 0;
    for (; k + 4 <= in_dim; k += 4)
        for (std::size_t j = 0; j < 4; ++j) {
            const double x = static_cast<double>(in[k + j]);
            for (std::size_t q = 0; q < Q; ++q) {
                Quad c;
                std::memcpy(&c, col + (k + j) * stride + 4 * q, sizeof(c));
                s[j][q] += c * x;
            }
        }
    for (std::size_t j = 0; k < in_dim; ++k, ++j) {
        const double x = static_cast<double>(in[k]);
        for (std::size_t q = 0; q < Q; ++q) {
            Quad c;
            std::memcpy(&c, col + k * stride + 4 * q, sizeof(c));
            s[j][q] += c * x;
        }
    }
    for (std::size_t q = 0; q < Q; ++q) {
        const Quad sum = (s[0][q] + s[1][q]) + (s[2][q] + s[3][q]);
        for (std::size_t i = 0; i < 4 && 4 * (q0 + q) + i < out_dim; ++i) out[4 * (q0 + q) + i] = sum[i];
    }
}

// out[r] = row r . in for every output, three vectors of outputs at a time
// (inlined into each build of apply())
template <class T>
[[gnu::always_inline]] inline void project(const double* columns, std::size_t in_dim, std::size_t out_dim, const T* in,
                                           double* out) {
    const std::size_t quads = (out_dim + 3) / 4;
    const std::size_t stride = 4 * quads;
    std::size_t q0 = 0;
    for (; q0 + 3 <= quads; q0 += 3) project_quads<3>(columns, stride, in_dim, q0, in, out, out_dim);
    if (quads - q0 == 2) project_quads<2>(columns, stride, in_dim, q0, in, out, out_dim);
    if (quads - q0 == 1) project_quads<1>(columns, stride, in_dim, q0, in, out, out_dim);
}

}  // namespace

Projection Projection::channel_means(std::size_t width, std::size_t channels, std::size_t blocks) {
    STEPSTONE_ASSERT(blocks >= 1 && blocks <= width);
    const std::size_t in = blocks * channels;
    std::vector<double> rows(channels * in, 0.0);
    for (std::size_t b = 0; b < blocks; ++b) {
        const std::size_t block_rows = (b + 1) * width / blocks - b * width / blocks;
        const double w = std::sqrt(static_cast<double>(block_rows) / static_cast<double>(width));
        for (std::size_t c = 0; c < channels; ++c) rows[c * in + b * channels + c] = w;
    }
    return Projection(in, channels, std::move(rows));
}

Projection Projection::principal(const float* points, std::size_t count, std::size_t in, std::size_t out,
                                 const Projection& fallback) {
    STEPSTONE_ASSERT(out >= 1 && out <= in && count >= 2);
    // covariance of an evenly spaced sample
    const std::size_t stride = std::max<std::size_t>(1, count / kMaxSample);
    std::vector<double> mean(in, 0.0), cov(in * in, 0.0), x(in);
    std::size_t n = 0;
    for (std::size_t i = 0; i < count; i += stride, ++n)
        for (std::size_t k = 0; k < in; ++k) mean[k] += points[i * in + k];
    for (double& m : mean) m /= static_cast<double>(n);
    for (std::size_t i = 0; i < count; i += stride) {
        for (std::size_t k = 0; k < in; ++k) x[k] = points[i * in + k] - mean[k];
        for (std::size_t r = 0; r < in; ++r)
            for (std::size_t c = r; c < in; ++c) cov[r * in + c] += x[r] * x[c];
    }
    for (std::size_t r = 0; r < in; ++r)
        for (std::size_t c = 0; c < r; ++c) cov[r * in + c] = cov[c * in + r];

    // eigenvectors by decreasing eigenvalue (Eigen returns them increasing)
    const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> matrix(
        cov.data(), static_cast<Eigen::Index>(in), static_cast<Eigen::Index>(in));
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(matrix);
    if (solver.info() != Eigen::Success) return fallback;
    const Eigen::MatrixXd& vectors = solver.eigenvectors();
    std::vector<double> rows(out * in);
    for (std::size_t r = 0; r < out; ++r) {
        const auto column = static_cast<Eigen::Index>(in - 1 - r);
        for (std::size_t k = 0; k < in; ++k) rows[r * in + k] = vectors(static_cast<Eigen::Index>(k), column);
    }
    orthonormalise(rows, out, in);
    Projection p(in, out, std::move(rows));
    if (!(p.orthonormality_error() <= kOrthonormalTolerance)) return fallback;
    return p;
}

STEPSTONE_KB_CLONES void Projection::apply(const double* in, double* out) const {
    project(columns_.data(), in_, out_, in, out);
}

STEPSTONE_KB_CLONES void Projection::apply(const float* in, double* out) const {
    project(columns_.data(), in_, out_, in, out);
}

Projection::Projection(std::size_t in, std::size_t out, std::vector<double> rows)
    : in_(in), out_(out), rows_(std::move(rows)) {
    const std::size_t stride = (out_ + 3) / 4 * 4;
    columns_.assign(in_ * stride, 0.0);
    for (std::size_t r = 0; r < out_; ++r)
        for (std::size_t k = 0; k < in_; ++k) columns_[k * stride + r] = rows_[r * in_ + k];
}

double Projection::orthonormality_error() const {
    double worst = 0.0;
    for (std::size_t i = 0; i < out_; ++i)
        for (std::size_t j = 0; j <= i; ++j) {
            const double dot = std::inner_product(rows_.begin() + static_cast<std::ptrdiff_t>(i * in_),
                                                  rows_.begin() + static_cast<std::ptrdiff_t>((i + 1) * in_),
                                                  rows_.begin() + static_cast<std::ptrdiff_t>(j * in_), 0.0);
            worst = std::max(worst, std::fabs(dot - (i == j ? 1.0 : 0.0)));
        }
    return worst;
}

}  // namespace stepstone::kb
