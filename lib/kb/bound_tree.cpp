#include "kb/bound_tree.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "core/assert.hpp"
#include "kb/detail/prefetch.hpp"
#include "kb/detail/simd.hpp"

namespace stepstone::kb {

namespace {

constexpr std::size_t kLanes = 8;
static_assert(BoundTree::kFanout == kLanes);
// eight floats as one value (GCC and Clang vector extension; lowered to the
// target's vector width)
typedef float Lanes __attribute__((vector_size(kLanes * sizeof(float))));

typedef std::int32_t Flags __attribute__((vector_size(kLanes * sizeof(std::int32_t))));

// the largest float <= x (x >= 0)
float float_at_most(double x) {
    float f = static_cast<float>(x);
    if (static_cast<double>(f) > x) {
        // the next float down (f > x >= 0; an infinite f becomes the largest)
        std::uint32_t bits;
        std::memcpy(&bits, &f, sizeof(bits));
        --bits;
        std::memcpy(&f, &bits, sizeof(f));
    }
    return f;
}

// bit j set when lane j of a comparison holds (lanes are all ones or all
// zeros); on x86 the sign bits of each half, one movmskps each (SSE is part
// of x86-64, so both builds have it), instead of eight lane extractions
[[gnu::always_inline]] inline unsigned lane_bits(const Flags& flags) {
#if defined(__x86_64__)
    typedef float Half __attribute__((vector_size(4 * sizeof(float))));
    Half low, high;
    std::memcpy(&low, &flags, sizeof(low));
    std::memcpy(&high, reinterpret_cast<const char*>(&flags) + sizeof(low), sizeof(high));
    return static_cast<unsigned>(__builtin_ia32_movmskps(low)) |
           static_cast<unsigned>(__builtin_ia32_movmskps(high)) << 4;
#else
    unsigned bits = 0;
    for (std::size_t j = 0; j < kLanes; ++j) bits |= static_cast<unsigned>(flags[j] & 1) << j;
    return bits;
#endif
}

std::size_t padded(std::size_t n) { return (n + kLanes - 1) / kLanes * kLanes; }

// what the search loop reads of a tree
struct View {
    const BoundTree::Wide* wides;
    const float* child_boxes;
    const BoundTree::Leaf* leaves;
    const float* coords;
    const std::uint32_t* ids;
    std::size_t dims;
};

// squared distances (float) from the query to the boxes of the children of
// wide node `index`, one lane per child: per coordinate the distance to the
// interval [low, high] (0 inside), as q - clamp(q, low, high), whose
// magnitude is bit for bit that of max(low - q, q - high, 0) (rounding is
// symmetric) in one operation fewer. Rounding is monotone, so each term is
// at most the rounded difference to any point of the box
[[gnu::always_inline]] inline void child_gaps(const View& t, std::uint32_t index, const float* query_f, float* out) {
    const float* low = t.child_boxes + std::size_t{index} * 2 * t.dims * kLanes;
    const float* high = low + t.dims * kLanes;
    Lanes acc = {};
    for (std::size_t d = 0; d < t.dims; ++d) {
        Lanes a, b;
        std::memcpy(&a, low + d * kLanes, sizeof(a));
        std::memcpy(&b, high + d * kLanes, sizeof(b));
        // the query coordinate in every lane: a scalar operand is broadcast
        // in one instruction and x - 0 folds to x (GCC assembles an
        // initializer list of eight x lane by lane)
        const Lanes q = query_f[d] - Lanes{};
        Lanes c = q > a ? q : a;
        c = c < b ? c : b;
        const Lanes gap = q - c;
        acc += gap * gap;
    }
    std::memcpy(out, &acc, sizeof(acc));
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

using Pending = BoundTree::Walk::Pending;
static_assert(BoundTree::Walk::kStack >= 64 * BoundTree::kFanout);

// starts loading what visiting `node` reads (of a leaf, the first
// dims x 8 floats: loading a whole leaf of 16 points measured slower; the
// hardware streams the rest)
[[gnu::always_inline]] inline void prefetch_node(const View& t, std::uint32_t node) {
    if (node & BoundTree::kLeafBit) {
        detail::prefetch(t.coords + t.leaves[node & ~BoundTree::kLeafBit].block, t.dims * kLanes * sizeof(float));
    } else {
        detail::prefetch(t.child_boxes + std::size_t{node} * 2 * t.dims * kLanes, 2 * t.dims * kLanes * sizeof(float));
    }
}

// pushes the children of wide node `node` whose box gap is within the limit,
// farthest first, so that the nearest is taken next. Without branches on the
// gaps (which children pass, and their order, are different at every node
// and a branch on them is mispredicted about as often as not): each child's
// rank among the passing ones comes from comparisons of all eight keys at
// once, every lane is stored at its rank (a lane that does not pass lands
// past the new top, where it is overwritten later) and the top moves by the
// number that pass. The key of a lane is its gap's bits (non-negative floats
// order as their bits do) with the lowest three replaced by the lane index,
// so keys are distinct; the order may differ from the gaps' for gaps within
// 2^-20 of each other, which only changes the order of the visit.
[[gnu::always_inline]] inline void expand(const View& t, std::uint32_t node, const float* query_f, double limit,
                                          Pending* stack, std::size_t& top) {
    const BoundTree::Wide& w = t.wides[node];
    float gaps[kLanes];
    child_gaps(t, node, query_f, gaps);
    Lanes g;
    std::memcpy(&g, gaps, sizeof(g));
    // a float gap is <= limit exactly when it is <= the largest float <= limit
    const Flags lane = {0, 1, 2, 3, 4, 5, 6, 7};
    const Flags pass = (g <= float_at_most(limit) - Lanes{}) & (lane < static_cast<std::int32_t>(w.count));
    Flags keys;
    std::memcpy(&keys, &g, sizeof(keys));
    keys = (keys & ~7) | lane;
    keys = pass ? keys : Flags{} - 1;
    // rank: the number of lanes with a greater key (comparisons give -1)
    Flags rank = {};
    rank -= __builtin_shufflevector(keys, keys, 1, 2, 3, 4, 5, 6, 7, 0) > keys;
    rank -= __builtin_shufflevector(keys, keys, 2, 3, 4, 5, 6, 7, 0, 1) > keys;
    rank -= __builtin_shufflevector(keys, keys, 3, 4, 5, 6, 7, 0, 1, 2) > keys;
    rank -= __builtin_shufflevector(keys, keys, 4, 5, 6, 7, 0, 1, 2, 3) > keys;
    rank -= __builtin_shufflevector(keys, keys, 5, 6, 7, 0, 1, 2, 3, 4) > keys;
    rank -= __builtin_shufflevector(keys, keys, 6, 7, 0, 1, 2, 3, 4, 5) > keys;
    rank -= __builtin_shufflevector(keys, keys, 7, 0, 1, 2, 3, 4, 5, 6) > keys;
    std::int32_t at[kLanes];
    std::memcpy(at, &rank, sizeof(at));
    Pending* base = stack + top;
    for (std::size_t c = 0; c < kLanes; ++c) base[at[c]] = {w.child[c], gaps[c]};
    const unsigned bits = lane_bits(pass);
    top += static_cast<std::size_t>(__builtin_popcount(bits));
    // the nearest child is taken next; a leaf is read in full at once, so
    // start loading it (loading every passing leaf stalled on the line-fill
    // buffers and measured slower)
    if ((bits & w.leaves) != 0 && (stack[top - 1].node & BoundTree::kLeafBit)) prefetch_node(t, stack[top - 1].node);
}

// calls report(id, gap) for the points of leaf `node` whose gap is within
// the limit; report returns the new limit
template <class Report>
[[gnu::always_inline]] inline double scan_leaf(const View& t, std::uint32_t node, const float* query_f, double limit,
                                               Report&& report) {
    const BoundTree::Leaf& leaf = t.leaves[node & ~BoundTree::kLeafBit];
    const std::size_t count = leaf.count, width = padded(count);
    const float* block = t.coords + leaf.block;
    // the points within the limit as bits (a float gap is <= limit exactly
    // when it is <= the largest float <= limit), 16 at a time, so that a leaf
    // of 9 to 16 points (the usual one) is one mask; padding points excluded.
    // `report` may shrink the limit: each point is checked against it again
    const Lanes lim = float_at_most(limit) - Lanes{};
    for (std::size_t i0 = 0; i0 < count; i0 += 2 * kLanes) {
        float gaps[2 * kLanes];
        Lanes g;
        leaf_gaps(t, block, width, i0, query_f, gaps);
        std::memcpy(&g, gaps, sizeof(g));
        unsigned bits = lane_bits(g <= lim);
        if (i0 + kLanes < count) {
            leaf_gaps(t, block, width, i0 + kLanes, query_f, gaps + kLanes);
            std::memcpy(&g, gaps + kLanes, sizeof(g));
            bits |= lane_bits(g <= lim) << kLanes;
        }
        bits &= (1u << std::min(2 * kLanes, count - i0)) - 1u;
        while (bits != 0) {
            const auto i = static_cast<std::size_t>(__builtin_ctz(bits));
            bits &= bits - 1;
            if (static_cast<double>(gaps[i]) <= limit) limit = report(t.ids[leaf.first + i0 + i], gaps[i]);
        }
    }
    return limit;
}

// depth first, nearer boxes first; a node is entered only while its box gap
// is within the (shrinking) limit
[[gnu::always_inline]] inline void search_loop(const View& t, std::uint32_t root, float root_gap, const float* query_f,
                                               double limit, BoundTree::Visit visit, void* context) {
    Pending stack[BoundTree::Walk::kStack];
    std::size_t top = 0;
    if (static_cast<double>(root_gap) > limit) return;
    stack[top++] = {root, root_gap};
    while (top > 0) {
        const Pending p = stack[--top];
        if (static_cast<double>(p.gap) > limit) continue;
        if (p.node & BoundTree::kLeafBit) {
            limit = scan_leaf(t, p.node, query_f, limit,
                              [&](std::uint32_t id, float) { return visit(context, std::size_t{id}); });
        } else {
            expand(t, p.node, query_f, limit, stack, top);
        }
    }
}

// one step of a Walk: the pending nodes within the limit, until a leaf has
// points within it (the caller checks them before the walk goes on, so the
// limit shrinks as in search_loop) or none is left; then starts loading the
// next node, which the walk reads at its next turn
[[gnu::always_inline]] inline void walk_step(const View& t, const float* query_f, double limit, Pending* stack,
                                             std::size_t& top, std::vector<BoundTree::Found>& found) {
    while (top > 0) {
        const Pending p = stack[--top];
        if (static_cast<double>(p.gap) > limit) continue;
        if (p.node & BoundTree::kLeafBit) {
            scan_leaf(t, p.node, query_f, limit, [&](std::uint32_t id, float gap) {
                found.push_back({id, gap});
                return limit;
            });
        } else {
            expand(t, p.node, query_f, limit, stack, top);
        }
        if (!found.empty()) break;
    }
    // the next node within the limit: the walk's next step reads it
    while (top > 0 && static_cast<double>(stack[top - 1].gap) > limit) --top;
    if (top > 0) prefetch_node(t, stack[top - 1].node);
}

void walk_generic(const View& t, const float* query_f, double limit, Pending* stack, std::size_t& top,
                  std::vector<BoundTree::Found>& found) {
    walk_step(t, query_f, limit, stack, top, found);
}

[[gnu::target("avx2")]] void walk_avx2(const View& t, const float* query_f, double limit, Pending* stack,
                                       std::size_t& top, std::vector<BoundTree::Found>& found) {
    walk_step(t, query_f, limit, stack, top, found);
}

void search_generic(const View& t, std::uint32_t root, float root_gap, const float* query_f, double limit,
                    BoundTree::Visit visit, void* context) {
    search_loop(t, root, root_gap, query_f, limit, visit, context);
}

[[gnu::target("avx2")]] void search_avx2(const View& t, std::uint32_t root, float root_gap, const float* query_f,
                                         double limit, BoundTree::Visit visit, void* context) {
    search_loop(t, root, root_gap, query_f, limit, visit, context);
}

}  // namespace

BoundTree::BoundTree(const float* points, std::size_t stride, std::size_t dims, std::size_t begin,
                     std::size_t end, std::size_t leaf_size)
    : stride_(stride),
      dims_(dims),
      box_dims_(padded(dims)),
      begin_(begin),
      end_(end),
      leaf_size_(std::max<std::size_t>(leaf_size, 1)),
      avx2_(detail::use_avx2()) {
    STEPSTONE_ASSERT(dims >= 1 && dims <= stride);
    STEPSTONE_ASSERT(end > begin && end - begin < kLeafBit);
    std::vector<std::uint32_t> order(end - begin);
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<std::uint32_t>(begin + i);
    std::vector<Binary> binary;
    std::vector<float> boxes;
    binary.reserve(2 * (order.size() / leaf_size_ + 1));
    build(order, 0, order.size(), points, binary, boxes);
    root_box_.assign(2 * box_dims_, 0.0f);
    for (std::size_t d = 0; d < dims_; ++d) {
        root_box_[d] = boxes[d];
        root_box_[box_dims_ + d] = boxes[dims_ + d];
    }
    root_ = collapse(0, binary, boxes, order, points);
    ids_ = std::move(order);
}

std::uint32_t BoundTree::build(std::vector<std::uint32_t>& order, std::size_t lo, std::size_t hi, const float* points,
                               std::vector<Binary>& binary, std::vector<float>& boxes) {
    const auto index = static_cast<std::uint32_t>(binary.size());
    binary.emplace_back();
    // the tight bounding box of the range; unless the range is small enough
    // or a single point repeated, split the axis of largest variance at the
    // mean, moved into the middle half of the points (the widest axis at the
    // median, as nanoflann does, gave boxes that a query visits ~25 % more
    // often on behaviour data: the widest axis is often set by a few outliers)
    const std::size_t box = boxes.size();
    boxes.resize(box + 2 * dims_, 0.0f);
    const auto n = static_cast<double>(hi - lo);
    std::size_t axis = 0;
    float width = 0.0f;
    double spread = -1.0;
    for (std::size_t d = 0; d < dims_; ++d) {
        float a = std::numeric_limits<float>::max(), b = std::numeric_limits<float>::lowest();
        double sum = 0.0, squares = 0.0;
        for (std::size_t i = lo; i < hi; ++i) {
            const float v = points[order[i] * stride_ + d];
            a = std::min(a, v);
            b = std::max(b, v);
            sum += v;
            squares += static_cast<double>(v) * v;
        }
        boxes[box + d] = a;
        boxes[box + dims_ + d] = b;
        width = std::max(width, b - a);
        const double variance = squares / n - (sum / n) * (sum / n);
        if (b > a && variance > spread) {
            spread = variance;
            axis = d;
        }
    }
    if (hi - lo <= leaf_size_ || width <= 0.0f) {
        binary[index].first = static_cast<std::uint32_t>(lo);
        binary[index].second = static_cast<std::uint32_t>(hi);
        return index;
    }
    const auto at = [&](std::uint32_t id) { return points[id * stride_ + axis]; };
    double sum = 0.0;
    for (std::size_t i = lo; i < hi; ++i) sum += at(order[i]);
    const double mean = sum / n;
    const auto below = std::count_if(order.begin() + static_cast<std::ptrdiff_t>(lo),
                                     order.begin() + static_cast<std::ptrdiff_t>(hi),
                                     [&](std::uint32_t id) { return static_cast<double>(at(id)) < mean; });
    const std::size_t margin = std::max<std::size_t>(1, (hi - lo) / 4);
    const std::size_t mid = std::clamp(lo + static_cast<std::size_t>(below), lo + margin, hi - margin);
    std::nth_element(order.begin() + static_cast<std::ptrdiff_t>(lo), order.begin() + static_cast<std::ptrdiff_t>(mid),
                     order.begin() + static_cast<std::ptrdiff_t>(hi),
                     [&](std::uint32_t a, std::uint32_t b) { return at(a) < at(b) || (at(a) == at(b) && a < b); });
    const std::uint32_t left = build(order, lo, mid, points, binary, boxes);
    const std::uint32_t right = build(order, mid, hi, points, binary, boxes);
    binary[index].first = left;
    binary[index].second = right;
    binary[index].leaf = false;
    return index;
}

std::uint32_t BoundTree::collapse(std::uint32_t node, const std::vector<Binary>& binary,
                                  const std::vector<float>& boxes, const std::vector<std::uint32_t>& order,
                                  const float* points) {
    if (binary[node].leaf) {
        // coordinate-major block; padding points are never reported
        const Binary& b = binary[node];
        Leaf leaf;
        leaf.first = b.first;
        leaf.count = b.second - b.first;
        leaf.block = coords_.size();
        const std::size_t width = padded(leaf.count);
        coords_.resize(coords_.size() + width * dims_, 0.0f);
        for (std::size_t d = 0; d < dims_; ++d)
            for (std::size_t i = 0; i < leaf.count; ++i)
                coords_[leaf.block + d * width + i] = points[std::size_t{order[leaf.first + i]} * stride_ + d];
        leaves_.push_back(leaf);
        return static_cast<std::uint32_t>(leaves_.size() - 1) | kLeafBit;
    }
    // the frontier below `node`, a level of the binary tree at a time (for
    // a balanced tree: the 8 nodes three levels down)
    std::vector<std::uint32_t> frontier{binary[node].first, binary[node].second};
    for (bool split = true; split;) {
        split = false;
        std::vector<std::uint32_t> next;
        std::size_t size = frontier.size();
        for (std::size_t i = 0; i < frontier.size(); ++i) {
            const Binary& b = binary[frontier[i]];
            if (!b.leaf && size + 1 <= kFanout) {
                next.push_back(b.first);
                next.push_back(b.second);
                ++size;
                split = true;
            } else {
                next.push_back(frontier[i]);
            }
        }
        frontier = std::move(next);
    }
    const auto index = static_cast<std::uint32_t>(wides_.size());
    wides_.emplace_back();
    const std::size_t box = child_boxes_.size();
    // unused lanes hold an empty box far away (its gap overflows to infinity)
    child_boxes_.resize(box + 2 * dims_ * kFanout, std::numeric_limits<float>::max());
    for (std::size_t c = 0; c < frontier.size(); ++c)
        for (std::size_t d = 0; d < dims_; ++d) {
            child_boxes_[box + d * kFanout + c] = boxes[std::size_t{frontier[c]} * 2 * dims_ + d];
            child_boxes_[box + (dims_ + d) * kFanout + c] = boxes[std::size_t{frontier[c]} * 2 * dims_ + dims_ + d];
        }
    wides_[index].count = static_cast<std::uint32_t>(frontier.size());
    for (std::size_t c = 0; c < frontier.size(); ++c) {
        const std::uint32_t child = collapse(frontier[c], binary, boxes, order, points);
        wides_[index].child[c] = child;
        if (child & kLeafBit) wides_[index].leaves |= 1u << c;
    }
    return index;
}

double BoundTree::root_gap(const float* query_f) const {
    // the box of all points, in double (a few coordinates, once per search)
    double gap2 = 0.0;
    for (std::size_t d = 0; d < dims_; ++d) {
        const double below = static_cast<double>(root_box_[d]) - static_cast<double>(query_f[d]);
        const double above = static_cast<double>(query_f[d]) - static_cast<double>(root_box_[box_dims_ + d]);
        const double gap = std::max({below, above, 0.0});
        gap2 += gap * gap;
    }
    return gap2;
}

void BoundTree::Walk::start(const BoundTree& tree, const float* query_f, double limit) {
    tree_ = &tree;
    query_f_ = query_f;
    top_ = 0;
    if (tree.root_gap(query_f) > limit) return;
    stack_[top_++] = {tree.root_, 0.0f};
    prefetch_node(tree.view<View>(), tree.root_);
}

void BoundTree::Walk::step(double limit, std::vector<Found>& found) {
    if (tree_->avx2_) {
        walk_avx2(tree_->view<View>(), query_f_, limit, stack_, top_, found);
    } else {
        walk_generic(tree_->view<View>(), query_f_, limit, stack_, top_, found);
    }
}

void BoundTree::search(const float* query_f, double limit, Visit visit, void* context) const {
    const View view = this->view<View>();
    if (root_gap(query_f) > limit) return;
    if (avx2_) {
        search_avx2(view, root_, 0.0f, query_f, limit, visit, context);
    } else {
        search_generic(view, root_, 0.0f, query_f, limit, visit, context);
    }
}

std::size_t BoundTree::near_leaf_point(const float* query_f) const {
    const View view = this->view<View>();
    std::uint32_t node = root_;
    while (!(node & kLeafBit)) {
        float gaps[kLanes];
        child_gaps(view, node, query_f, gaps);
        const Wide& w = wides_[node];
        std::size_t best = 0;
        for (std::size_t c = 1; c < w.count; ++c)
            if (gaps[c] < gaps[best]) best = c;
        node = w.child[best];
    }
    const Leaf& leaf = leaves_[node & ~kLeafBit];
    const std::size_t width = padded(leaf.count);
    std::size_t best = ids_[leaf.first];
    float best_gap = std::numeric_limits<float>::infinity();
    for (std::size_t i0 = 0; i0 < leaf.count; i0 += kLanes) {
        float gaps[kLanes];
        leaf_gaps(view, coords_.data() + leaf.block, width, i0, query_f, gaps);
        for (std::size_t i = 0; i < std::min<std::size_t>(kLanes, leaf.count - i0); ++i) {
            if (gaps[i] < best_gap) {
                best_gap = gaps[i];
                best = ids_[leaf.first + i0 + i];
            }
        }
    }
    return best;
}

double BoundTree::bytes_per_point() const {
    const std::size_t floats = coords_.size() + child_boxes_.size() + root_box_.size();
    return static_cast<double>(floats * sizeof(float) + wides_.size() * sizeof(Wide) + leaves_.size() * sizeof(Leaf)) /
               static_cast<double>(size()) +
           static_cast<double>(sizeof(std::uint32_t));
}

}  // namespace stepstone::kb
