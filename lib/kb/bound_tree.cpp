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

// what the search loop reads of a tree
struct View {
    const BoundTree::Node* nodes;
    const float* boxes;
    const float* coords;
    const std::uint32_t* ids;
    std::size_t dims;
    std::size_t box_dims;
};

// squared distance (float) from the query to the box of node `index`: per
// coordinate the distance to the interval [low, high] (0 inside); rounding is
// monotone, so each term is at most the rounded difference to any point of
// the box
[[gnu::always_inline]] inline float box_gap(const View& t, std::uint32_t index, const float* query_f) {
    const float* low = t.boxes + std::size_t{index} * 2 * t.box_dims;
    const float* high = low + t.box_dims;
    const Lanes zero = {};
    Lanes acc = {};
    for (std::size_t d = 0; d < t.box_dims; d += kLanes) {
        Lanes q, a, b;
        std::memcpy(&q, query_f + d, sizeof(q));
        std::memcpy(&a, low + d, sizeof(a));
        std::memcpy(&b, high + d, sizeof(b));
        const Lanes below = a - q, above = q - b;
        Lanes gap = below > above ? below : above;
        gap = gap > zero ? gap : zero;
        acc += gap * gap;
    }
    return ((acc[0] + acc[1]) + (acc[2] + acc[3])) + ((acc[4] + acc[5]) + (acc[6] + acc[7]));
}

// gaps of a leaf's points [i0, i0 + 8) (padding points included)
[[gnu::always_inline]] inline void leaf_gaps(const View& t, const float* block, std::size_t width, std::size_t i0,
                                             const float* query_f, float* out) {
    Lanes acc = {};
    for (std::size_t d = 0; d < t.dims; ++d) {
        Lanes row;
        std::memcpy(&row, block + d * width + i0, sizeof(row));
        const Lanes diff = query_f[d] - row;
        acc += diff * diff;
    }
    std::memcpy(out, &acc, sizeof(acc));
}

// depth first, the nearer child first; a node is entered only while its box
// gap is within the (shrinking) limit
[[gnu::always_inline]] inline void search_loop(const View& t, const float* query_f, double limit,
                                               BoundTree::Visit visit, void* context) {
    struct Pending {
        std::uint32_t node;
        float gap;
    };
    // each level of the descent leaves at most one pending sibling
    Pending stack[80];
    std::size_t top = 0;
    const float root = box_gap(t, 0, query_f);
    if (static_cast<double>(root) > limit) return;
    stack[top++] = {0, root};
    while (top > 0) {
        const Pending p = stack[--top];
        if (static_cast<double>(p.gap) > limit) continue;
        std::uint32_t index = p.node;
        // descend to a leaf, leaving the farther children behind
        while (t.nodes[index].axis >= 0) {
            const BoundTree::Node& n = t.nodes[index];
            const float a = box_gap(t, n.first, query_f), b = box_gap(t, n.second, query_f);
            const bool first_near = a <= b;
            const std::uint32_t near = first_near ? n.first : n.second, far = first_near ? n.second : n.first;
            const float near_gap = first_near ? a : b, far_gap = first_near ? b : a;
            if (static_cast<double>(far_gap) <= limit) stack[top++] = {far, far_gap};
            if (static_cast<double>(near_gap) > limit) break;
            index = near;
        }
        const BoundTree::Node& leaf = t.nodes[index];
        if (leaf.axis >= 0) continue;  // the nearer child was out of reach
        const std::size_t count = leaf.second - leaf.first, width = padded(count);
        const float* block = t.coords + leaf.block;
        for (std::size_t i0 = 0; i0 < count; i0 += kLanes) {
            float gaps[kLanes];
            leaf_gaps(t, block, width, i0, query_f, gaps);
            const std::size_t n = std::min(kLanes, count - i0);
            for (std::size_t i = 0; i < n; ++i)
                if (static_cast<double>(gaps[i]) <= limit) limit = visit(context, std::size_t{t.ids[leaf.first + i0 + i]});
        }
    }
}

void search_generic(const View& t, const float* query_f, double limit, BoundTree::Visit visit, void* context) {
    search_loop(t, query_f, limit, visit, context);
}

[[gnu::target("avx2")]] void search_avx2(const View& t, const float* query_f, double limit, BoundTree::Visit visit,
                                         void* context) {
    search_loop(t, query_f, limit, visit, context);
}

bool cpu_has_avx2() {
#if defined(__x86_64__) || defined(__i386__)
    return __builtin_cpu_supports("avx2");
#else
    return false;
#endif
}

}  // namespace

BoundTree::BoundTree(const float* points, std::size_t stride, std::size_t dims, std::size_t begin, std::size_t end,
                     std::size_t leaf_size)
    : stride_(stride),
      dims_(dims),
      box_dims_(padded(dims)),
      begin_(begin),
      end_(end),
      leaf_size_(std::max<std::size_t>(leaf_size, 1)),
      avx2_(cpu_has_avx2()) {
    STEPSTONE_ASSERT(dims >= 1 && dims <= stride);
    STEPSTONE_ASSERT(end > begin && end <= std::numeric_limits<std::uint32_t>::max());
    std::vector<std::uint32_t> order(end - begin);
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<std::uint32_t>(begin + i);
    nodes_.reserve(2 * (order.size() / leaf_size_ + 1));
    boxes_.reserve(nodes_.capacity() * 2 * box_dims_);
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
    const std::size_t box = boxes_.size();
    boxes_.resize(box + 2 * box_dims_, 0.0f);
    std::size_t axis = 0;
    float width = 0.0f;
    for (std::size_t d = 0; d < dims_; ++d) {
        float a = std::numeric_limits<float>::max(), b = std::numeric_limits<float>::lowest();
        for (std::size_t i = lo; i < hi; ++i) {
            a = std::min(a, points[order[i] * stride_ + d]);
            b = std::max(b, points[order[i] * stride_ + d]);
        }
        boxes_[box + d] = a;
        boxes_[box + box_dims_ + d] = b;
        if (b - a > width) {
            width = b - a;
            axis = d;
        }
    }
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
    const std::uint32_t left = build(order, lo, mid, points);
    const std::uint32_t right = build(order, mid, hi, points);
    Node& n = nodes_[index];
    n.first = left;
    n.second = right;
    n.axis = static_cast<std::int32_t>(axis);
    return index;
}

void BoundTree::search(const float* query_f, double limit, Visit visit, void* context) const {
    const View view{nodes_.data(), boxes_.data(), coords_.data(), ids_.data(), dims_, box_dims_};
    if (avx2_) {
        search_avx2(view, query_f, limit, visit, context);
    } else {
        search_generic(view, query_f, limit, visit, context);
    }
}

std::size_t BoundTree::near_leaf_point(const float* query_f) const {
    const View view{nodes_.data(), boxes_.data(), coords_.data(), ids_.data(), dims_, box_dims_};
    std::uint32_t index = 0;
    while (nodes_[index].axis >= 0) {
        const Node& n = nodes_[index];
        index = box_gap(view, n.second, query_f) < box_gap(view, n.first, query_f) ? n.second : n.first;
    }
    const Node& leaf = nodes_[index];
    const std::size_t count = leaf.second - leaf.first, width = padded(count);
    std::size_t best = ids_[leaf.first];
    float best_gap = std::numeric_limits<float>::infinity();
    for (std::size_t i0 = 0; i0 < count; i0 += kLanes) {
        float gaps[kLanes];
        leaf_gaps(view, coords_.data() + leaf.block, width, i0, query_f, gaps);
        for (std::size_t i = 0; i < std::min(kLanes, count - i0); ++i) {
            if (gaps[i] < best_gap) {
                best_gap = gaps[i];
                best = ids_[leaf.first + i0 + i];
            }
        }
    }
    return best;
}

double BoundTree::bytes_per_point() const {
    return static_cast<double>((coords_.size() + boxes_.size()) * sizeof(float)) / static_cast<double>(size()) +
           static_cast<double>(sizeof(std::uint32_t)) +
           static_cast<double>(nodes_.size() * sizeof(Node)) / static_cast<double>(size());
}

}  // namespace stepstone::kb
