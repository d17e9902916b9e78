#include "kb/segments.hpp"

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

Segments as_segments(std::span<const float> values, std::size_t dim) {
    if (dim == 0) throw DataError("segments: dimension must be >= 1, got 0");
    if (values.size() % dim != 0) {
        throw DataError(concat("segments: ", values.size(), " values is not a whole number of segments of ",
                               dim, " values"));
    }
    return Segments{values, dim};
}

}  // namespace stepstone::kb
