#pragma once

#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <utility>
#include <vector>

#include "kb/detail/huge_pages.hpp"

namespace stepstone::kb {

/// A static KD-tree over the first `dims` coordinates of float points stored
/// `stride` floats apart, built for SegmentIndex's lower bounds.
///
/// Built by binary splits (the axis of largest variance, at the mean moved
/// into the middle half of the points) down to leaves of at most `leaf_size`
/// points, then collapsed into nodes of up to kFanout children: each node
/// keeps the tight bounding boxes of its children (all `dims` coordinates, not
/// only the split planes on the path) coordinate-major, so the query's
/// distances to its 8 children are computed 8 at a time, and each leaf keeps
/// its points coordinate-major in a block padded to a multiple of 8 points.
/// Gaps and box distances are sums of squares in single precision, each
/// within a relative (dims + 2) x 2^-24 of its exact value, and the exact box
/// distance of a node never exceeds the exact gap of a point it holds; callers
/// put that slack and the rounding of the points into their limit (see
/// SegmentIndex). The search loop has a generic and an AVX2 build (same
/// arithmetic, picked at construction from the CPU).
class BoundTree {
public:
    /// Called for a point whose gap is within the limit; returns the new
    /// limit (which may only shrink).
    using Visit = double (*)(void* context, std::size_t id);

    /// Builds over points[id * stride, (id + 1) * stride) for id in [begin, end).
    BoundTree(const float* points, std::size_t stride, std::size_t dims, std::size_t begin, std::size_t end,
              std::size_t leaf_size);

    std::size_t begin() const { return begin_; }
    std::size_t end() const { return end_; }
    std::size_t size() const { return end_ - begin_; }

    /// Calls `visit(context, id)` for the points whose float gap to `query_f`
    /// (padded with zeros to a multiple of 8 coordinates) is <= the current
    /// limit, depth first with the child whose box is nearer first, skipping
    /// every node whose box lies farther than the limit. `visit` returns the
    /// new limit, e.g. the bound of the best match found so far.
    void search(const float* query_f, double limit, Visit visit, void* context) const;

    /// As search(), with a callable `visit(id) -> double`.
    template <class F>
    void search(const float* query_f, double limit, F&& visit) const {
        search(
            query_f, limit, [](void* c, std::size_t id) { return (*static_cast<std::remove_reference_t<F>*>(c))(id); },
            const_cast<void*>(static_cast<const void*>(&visit)));
    }

    /// A point a Walk found within its limit, and its float gap.
    struct Found {
        std::uint32_t id;
        float gap;
    };

    /// One search() made resumable a node at a time, so that the searches of
    /// several queries can take turns: each step ends by prefetching what the
    /// walk's next step reads, and the other walks' steps hide that latency
    /// (SegmentIndex::nearest_within_batch). Visits the nodes of search() in
    /// the same order for the same limits.
    class Walk {
    public:
        /// Starts a search of `tree` (which must outlive the walk) for
        /// `query_f`, padded as for search().
        void start(const BoundTree& tree, const float* query_f, double limit);
        /// True once no node is left within the limits given.
        bool done() const { return top_ == 0; }
        /// Takes the next node within `limit` (skipping the others): a wide
        /// node pushes its children within the limit, nearer first; a leaf
        /// appends its points whose gap is within the limit to `found`.
        void step(double limit, std::vector<Found>& found);

        /// A node left for later and its box gap.
        struct Pending {
            std::uint32_t node;
            float gap;
        };
        /// Each wide node on the path leaves at most kFanout - 1 pending
        /// children, and an expansion writes kFanout entries past the top;
        /// trees are far shallower than 63 wide levels.
        static constexpr std::size_t kStack = 64 * 8;

    private:
        const BoundTree* tree_ = nullptr;
        const float* query_f_ = nullptr;
        std::size_t top_ = 0;
        Pending stack_[kStack];
    };

    /// The point of the leaf the query descends to with the smallest gap (an
    /// arbitrary but real point, for an upper bound).
    std::size_t near_leaf_point(const float* query_f) const;

    /// Bytes held per point (coordinates, boxes, ids and nodes).
    double bytes_per_point() const;

    /// True when the search loops run their AVX2 build: the CPU has AVX2 and
    /// the environment does not set STEPSTONE_KB_GENERIC (read once).
    bool avx2() const { return avx2_; }

    /// Children of an inner node (up to kFanout): wide node indices, or leaf
    /// indices with kLeafBit set.
    static constexpr std::size_t kFanout = 8;
    static constexpr std::uint32_t kLeafBit = 0x80000000u;
    struct Wide {
        std::uint32_t child[kFanout] = {};
        std::uint32_t count = 0;
        std::uint32_t leaves = 0;  // bit c set when child c is a leaf
    };
    struct Leaf {
        std::uint32_t first = 0;   // point range in leaf order
        std::uint32_t count = 0;
        std::uint64_t block = 0;   // offset of its coordinate block in coords_
    };

private:
    // binary KD-tree built first (split of the axis of largest variance, see
    // build()), then collapsed into nodes of up to kFanout children
    struct Binary {
        std::uint32_t first = 0;   // leaf: point range in leaf order; inner: children
        std::uint32_t second = 0;
        bool leaf = true;
    };
    // squared distance (double) from the query to the box of all points
    double root_gap(const float* query_f) const;
    // the arrays a search reads, as the search loop's aggregate `V`
    template <class V>
    V view() const {
        return V{wides_.data(), child_boxes_.data(), leaves_.data(), coords_.data(), ids_.data(), dims_};
    }
    std::uint32_t build(std::vector<std::uint32_t>& order, std::size_t lo, std::size_t hi, const float* points,
                        std::vector<Binary>& binary, std::vector<float>& boxes);
    std::uint32_t collapse(std::uint32_t node, const std::vector<Binary>& binary, const std::vector<float>& boxes,
                           const std::vector<std::uint32_t>& order, const float* points);

    std::size_t stride_;
    std::size_t dims_;
    std::size_t box_dims_;  // dims_ padded to a multiple of 8
    std::size_t begin_;
    std::size_t end_;
    std::size_t leaf_size_;
    bool avx2_ = false;
    std::uint32_t root_ = 0;           // a wide node, or a leaf with kLeafBit
    std::vector<float> root_box_;      // box_dims_ lowest then box_dims_ highest coordinates (padding 0)
    std::vector<Wide> wides_;
    // per wide node: dims_ rows of kFanout lowest coordinates of its children's
    // boxes, then dims_ rows of the highest (unused children: an empty box far away)
    std::vector<float> child_boxes_;
    std::vector<Leaf> leaves_;
    detail::HugeVector<float> coords_;        // leaf blocks: dims_ rows of the leaf's points, padded to 8
    std::vector<std::uint32_t> ids_;   // their ids, in leaf order
};

}  // namespace stepstone::kb
