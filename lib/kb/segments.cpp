#include "kb/segments.hpp"

#include <cmath>

#include "core/error.hpp"
#include "core/text.hpp"

namespace stepstone::kb {

std::size_t segment_count(std::size_t steps, std::size_t width) {
    return width == 0 ? 0 : steps / width;
}

Segments segment_behaviour(std::span<const float> behaviour, std::size_t channels, std::size_t width) {
    if (channels == 0) throw DataError("behaviour: channels must be >= 1, got 0");
    if (width == 0) throw DataError("behaviour: segment_width must be >= 1, got 0");
    if (behaviour.size() % channels != 0) {
        throw DataError(concat("behaviour: ", behaviour.size(), " values is not a whole number of rows of ",
                               channels, " channels"));
    }
    // rows are time steps, so a window of width rows is contiguous
    const std::size_t steps = behaviour.size() / channels;
    const std::size_t dim = width * channels;
    return Segments{behaviour.first(segment_count(steps, width) * dim), dim};
}

std::size_t first_non_finite(std::span<const float> values) {
    // v - v is 0 for a finite v and NaN otherwise, so eight running sums of
    // it stay 0 exactly when every value is finite (a quick pass, then a
    // search only on failure)
    float lanes[8] = {};
    std::size_t k = 0;
    for (; k + 8 <= values.size(); k += 8)
        for (std::size_t j = 0; j < 8; ++j) lanes[j] += values[k + j] - values[k + j];
    bool finite = true;
    for (const float lane : lanes) finite = finite && lane == 0.0f;
    // all finite so far: only the tail is left to check
    if (!finite) k = 0;
    for (; k < values.size(); ++k)
        if (!std::isfinite(values[k])) return k;
    return values.size();
}

void require_finite(std::span<const float> values, std::size_t dim, std::size_t first) {
    if (const std::size_t k = first_non_finite(values); k < values.size()) {
        throw DataError(concat("segment ", first + k / dim, " has a non-finite value at position ", k % dim));
    }
}

Segments as_segments(std::span<const float> values, std::size_t dim) {
    if (dim == 0) throw DataError("segments: dimension must be >= 1, got 0");
    if (values.size() % dim != 0) {
        throw DataError(concat("segments: ", values.size(), " values is not a whole number of segments of ",
                               dim, " values"));
    }
    return Segments{values, dim};
}

}  // namespace stepstone::kb
