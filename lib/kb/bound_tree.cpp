#include "kb/bound_tree.hpp"

#include <algorithm>
#include <cstring>
#include <limits>

#include "core/assert.hpp"

namespace stepstone::kb {

namespace {

constexpr std::size_t kLanes = 8;
// eight floats as one value (GCC and Clang vector extension; lowered to the
// target's vector width)
typedef float Lanes __attribute__((vector_size(kLanes * sizeof(float))));

std::size_t padded(std::size_t n) { return (n + kLanes - 1) / kLanes * kLanes; }

}  // namespace

BoundTree::BoundTree(const float* points, std::size_t stride, std::size_t dims, std::size_t begin, std::size_t end,
                     std::size_t leaf_size)
    : stride_(stride), dims_(dims), begin_(begin), end_(end), leaf_size_(std::max<std::size_t>(leaf_size, 1)) {
    STEPSTONE_ASSERT(dims >= 1 && dims <= stride);
    STEPSTONE_ASSERT(end > begin && end <= std::numeric_limits<std::uint32_t>::max());
    std::vector<std::uint32_t> order(end - begin);
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<std::uint32_t>(begin + i);
    nodes_.reserve(2 * (order.size() / leaf_size_ + 1));
    build(order, 0, order.size(), points);
    // leaf blocks, coordinate-major; padding points are never reported
    for (Node& n : nodes_) {
        if (n.axis >= 0) continue;
        const std::size_t count = n.second - n.first, width = padded(count);
        n.block = coords_.size();
        coords_.resize(coords_.size() + width * dims_, 0.0f);
        for (std::size_t d = 0; d < dims_; ++d)
            for (std::size_t i = 0; i < count; ++i)
                coords_[n.block + d * width + i] = points[std::size_t{order[n.first + i]} * stride_ + d];
    }
    ids_ = std::move(order);
}

std::uint32_t BoundTree::build(std::vector<std::uint32_t>& order, std::size_t lo, std::size_t hi,
                               const float* points) {
    const auto index = static_cast<std::uint32_t>(nodes_.size());
    nodes_.emplace_back();
    // the tight bounding box of the range; split its widest axis at the
    // median, unless the range is small enough or a single point repeated
    std::vector<float> bounds(2 * dims_);
    std::size_t axis = 0;
    float width = 0.0f;
    for (std::size_t d = 0; d < dims_; ++d) {
        float a = std::numeric_limits<float>::max(), b = std::numeric_limits<float>::lowest();
        for (std::size_t i = lo; i < hi; ++i) {
            a = std::min(a, points[order[i] * stride_ + d]);
            b = std::max(b, points[order[i] * stride_ + d]);
        }
        bounds[d] = a;
        bounds[dims_ + d] = b;
        if (b - a > width) {
            width = b - a;
            axis = d;
        }
    }
    if (index == 0) box_ = bounds;
    if (hi - lo <= leaf_size_ || width <= 0.0f) {
        nodes_[index].first = static_cast<std::uint32_t>(lo);
        nodes_[index].second = static_cast<std::uint32_t>(hi);
        return index;
    }
    const std::size_t mid = lo + (hi - lo) / 2;
    const auto at = [&](std::uint32_t id) { return points[id * stride_ + axis]; };
    std::nth_element(order.begin() + static_cast<std::ptrdiff_t>(lo), order.begin() + static_cast<std::ptrdiff_t>(mid),
                     order.begin() + static_cast<std::ptrdiff_t>(hi),
                     [&](std::uint32_t a, std::uint32_t b) { return at(a) < at(b) || (at(a) == at(b) && a < b); });
    float low = std::numeric_limits<float>::lowest(), high = std::numeric_limits<float>::max();
    for (std::size_t i = lo; i < mid; ++i) low = std::max(low, at(order[i]));
    for (std::size_t i = mid; i < hi; ++i) high = std::min(high, at(order[i]));
    const std::uint32_t left = build(order, lo, mid, points);
    const std::uint32_t right = build(order, mid, hi, points);
    Node& n = nodes_[index];
    n.first = left;
    n.second = right;
    n.axis = static_cast<std::int32_t>(axis);
    n.low = low;
    n.high = high;
    return index;
}

void BoundTree::scan_leaf(const Node& leaf, std::size_t first, const float* query_f, float* gaps) const {
    const std::size_t width = padded(leaf.second - leaf.first);
    const float* block = coords_.data() + leaf.block;
    const std::size_t end = std::min(width, first + kChunk);
    for (std::size_t i0 = first; i0 < end; i0 += kLanes) {
        // eight points at a time: one vector of lanes per coordinate
        Lanes acc = {};
        for (std::size_t d = 0; d < dims_; ++d) {
            Lanes row;
            std::memcpy(&row, block + d * width + i0, sizeof(row));
            const Lanes diff = query_f[d] - row;
            acc += diff * diff;
        }
        std::memcpy(gaps + (i0 - first), &acc, sizeof(acc));
    }
}

void BoundTree::within(const double* query, const float* query_f, double limit,
                       std::vector<std::pair<double, std::size_t>>& out) const {
    // distance to the bounding box of all points, one term per axis
    std::vector<double> sides(dims_, 0.0);
    double box = 0.0;
    for (std::size_t d = 0; d < dims_; ++d) {
        const double below = static_cast<double>(box_[d]) - query[d];
        const double above = query[d] - static_cast<double>(box_[dims_ + d]);
        const double gap = below > 0 ? below : (above > 0 ? above : 0.0);
        sides[d] = gap * gap;
        box += sides[d];
    }
    if (box > limit) return;
    search(0, box, sides, query, query_f, limit, out);
}

void BoundTree::search(std::uint32_t index, double box, std::vector<double>& sides, const double* query,
                       const float* query_f, double limit, std::vector<std::pair<double, std::size_t>>& out) const {
    const Node& n = nodes_[index];
    if (n.axis < 0) {
        float gaps[kChunk];
        const std::size_t count = n.second - n.first;
        for (std::size_t c0 = 0; c0 < count; c0 += kChunk) {
            scan_leaf(n, c0, query_f, gaps);
            for (std::size_t i = c0; i < std::min(count, c0 + kChunk); ++i)
                if (static_cast<double>(gaps[i - c0]) <= limit) out.emplace_back(gaps[i - c0], ids_[n.first + i]);
        }
        return;
    }
    // the query's side first, with the same box; the other side's box
    // differs from this one on the split axis only
    const auto axis = static_cast<std::size_t>(n.axis);
    const double to_low = query[axis] - static_cast<double>(n.low);
    const double to_high = query[axis] - static_cast<double>(n.high);
    std::uint32_t near = n.first, far = n.second;
    double cut = to_high * to_high;
    if (to_low + to_high >= 0) {
        near = n.second;
        far = n.first;
        cut = to_low * to_low;
    }
    search(near, box, sides, query, query_f, limit, out);
    const double saved = sides[axis];
    const double far_box = box + cut - saved;
    if (far_box <= limit) {
        sides[axis] = cut;
        search(far, far_box, sides, query, query_f, limit, out);
        sides[axis] = saved;
    }
}

std::size_t BoundTree::near_leaf_point(const double* query, const float* query_f) const {
    std::uint32_t index = 0;
    while (nodes_[index].axis >= 0) {
        const Node& n = nodes_[index];
        const auto axis = static_cast<std::size_t>(n.axis);
        const double to_low = query[axis] - static_cast<double>(n.low);
        const double to_high = query[axis] - static_cast<double>(n.high);
        index = to_low + to_high >= 0 ? n.second : n.first;
    }
    const Node& leaf = nodes_[index];
    // the first chunk is enough for an upper bound
    float gaps[kChunk];
    scan_leaf(leaf, 0, query_f, gaps);
    std::size_t best = ids_[leaf.first];
    float best_gap = std::numeric_limits<float>::infinity();
    for (std::size_t i = 0; i < std::min<std::size_t>(leaf.second - leaf.first, kChunk); ++i) {
        if (gaps[i] < best_gap) {
            best_gap = gaps[i];
            best = ids_[leaf.first + i];
        }
    }
    return best;
}

double BoundTree::bytes_per_point() const {
    return static_cast<double>(coords_.size() * sizeof(float)) / static_cast<double>(size()) +
           static_cast<double>(sizeof(std::uint32_t)) +
           static_cast<double>(nodes_.size() * sizeof(Node)) /
               static_cast<double>(size());
}

}  // namespace stepstone::kb
