#include "kb/distance.hpp"

#include "kb/detail/simd.hpp"

namespace stepstone::kb {

namespace {

// values between two checks of the bound in squared_distance_up_to
constexpr std::size_t kCheckEvery = 32;

struct Lanes {
    double l[kDistanceLanes] = {};

    // adds the squared differences of values [begin, end); begin is a
    // multiple of kDistanceLanes, so value k goes to lane k % 8
    void add(const float* a, const float* b, std::size_t begin, std::size_t end) {
        std::size_t k = begin;
        for (; k + kDistanceLanes <= end; k += kDistanceLanes) {
            for (std::size_t j = 0; j < kDistanceLanes; ++j) {
                const double d = static_cast<double>(a[k + j]) - static_cast<double>(b[k + j]);
                l[j] += d * d;
            }
        }
        for (std::size_t j = 0; k < end; ++k, ++j) {
            const double d = static_cast<double>(a[k]) - static_cast<double>(b[k]);
            l[j] += d * d;
        }
    }

    double total() const { return ((l[0] + l[1]) + (l[2] + l[3])) + ((l[4] + l[5]) + (l[6] + l[7])); }
};

}  // namespace

STEPSTONE_KB_CLONES double squared_distance(const float* a, const float* b, std::size_t dim) {
    Lanes lanes;
    lanes.add(a, b, 0, dim);
    return lanes.total();
}

STEPSTONE_KB_CLONES double squared_distance_up_to(const float* a, const float* b, std::size_t dim, double bound) {
    Lanes lanes;
    std::size_t k = 0;
    // a partial total never exceeds the full one: every lane only grows
    // (adding a square rounds to a value >= the lane) and the final sum is
    // monotone in each lane
    while (k < dim) {
        const std::size_t end = k + kCheckEvery < dim ? k + kCheckEvery : dim;
        lanes.add(a, b, k, end);
        k = end;
        if (k < dim) {
            const double partial = lanes.total();
            if (partial > bound) return partial;
        }
    }
    return lanes.total();
}

}  // namespace stepstone::kb
