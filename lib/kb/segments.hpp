#pragma once

#include <cstddef>
#include <span>

namespace stepstone::kb {

/// Non-owning view of segments stored one after another: segment i occupies
/// values[i * dim, (i + 1) * dim). The viewed floats must outlive the view.
struct Segments {
    std::span<const float> values;  ///< every segment's values, back to back
    std::size_t dim = 0;            ///< values per segment (segment_width x channels)

    /// Number of whole segments in the view (0 when dim is 0).
    std::size_t size() const { return dim == 0 ? 0 : values.size() / dim; }
    /// The values of segment i (i < size()).
    std::span<const float> operator[](std::size_t i) const { return values.subspan(i * dim, dim); }
};

/// Number of non-overlapping windows of `width` steps in `steps` steps: a
/// trailing partial window is dropped, so 4010 steps of width 20 give 200.
/// Returns 0 when width is 0.
std::size_t segment_count(std::size_t steps, std::size_t width);

/// Cuts a behaviour matrix into non-overlapping windows of `width` time steps.
///
/// `behaviour` is row-major with one row per time step and `channels` columns
/// (the paper: 4000 rows of 15 channels). A segment is `width` consecutive
/// rows, i.e. width * channels contiguous floats, so the result views the
/// first segment_count(rows, width) * width * channels values of `behaviour`
/// without copying; a trailing partial window is dropped.
///
/// Throws DataError if channels or width is 0, or if behaviour.size() is not
/// a multiple of channels.
Segments segment_behaviour(std::span<const float> behaviour, std::size_t channels, std::size_t width);

/// Index of the first value of `values` that is NaN or infinite, or
/// values.size() when all are finite.
std::size_t first_non_finite(std::span<const float> values);

/// Throws DataError naming the first segment with a non-finite value and its
/// position, e.g. "segment 3 has a non-finite value at position 17", where
/// `values` holds segments of `dim` values numbered from `first`.
void require_finite(std::span<const float> values, std::size_t dim, std::size_t first = 0);

/// Views `values` as segments of `dim` floats.
/// Throws DataError if dim is 0 or values.size() is not a multiple of dim.
Segments as_segments(std::span<const float> values, std::size_t dim);

}  // namespace stepstone::kb
