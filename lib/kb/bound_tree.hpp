#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace stepstone::kb {

/// A static KD-tree over the first `dims` coordinates of float points stored
/// `stride` floats apart, built for SegmentIndex's lower bounds.
///
/// Each leaf keeps its points coordinate-major in a block padded to a
/// multiple of 8 points, so a visited leaf is scanned with the query's
/// coordinates broadcast over 8 points at a time (single precision: a sum of
/// `dims` squares, within a relative (dims + 2) x 2^-24 of the exact gap). The
/// traversal computes the distance from the query to each node's box in
/// double, incrementally as nanoflann does (a child's box differs from its
/// parent's on the split axis only); a node is skipped only when that distance
/// exceeds the caller's limit, and leaf points are reported when their float
/// gap is <= the limit. Callers put the rounding slack into the limit (see
/// SegmentIndex).
class BoundTree {
public:
    /// Builds over points[id * stride, (id + 1) * stride) for id in [begin, end).
    BoundTree(const float* points, std::size_t stride, std::size_t dims, std::size_t begin, std::size_t end,
              std::size_t leaf_size);

    std::size_t begin() const { return begin_; }
    std::size_t end() const { return end_; }
    std::size_t size() const { return end_ - begin_; }

    /// Appends (gap, id) for every point whose float gap to `query_f` is <=
    /// `limit`, skipping boxes whose distance to `query` (double) exceeds it.
    void within(const double* query, const float* query_f, double limit,
                std::vector<std::pair<double, std::size_t>>& out) const;
    /// The point of the leaf the query descends to with the smallest gap (an
    /// arbitrary but real point, for an upper bound).
    std::size_t near_leaf_point(const double* query, const float* query_f) const;

    /// Bytes held per point (coordinates, ids, nodes).
    double bytes_per_point() const;

private:
    struct Node {
        std::uint32_t first = 0;   // leaf: point range in leaf order; inner: children
        std::uint32_t second = 0;
        std::uint64_t block = 0;   // leaf: offset of its coordinate block in coords_
        std::int32_t axis = -1;    // -1 for a leaf
        float low = 0.0f;          // inner: largest coordinate on the left
        float high = 0.0f;         // inner: smallest coordinate on the right
    };

    std::uint32_t build(std::vector<std::uint32_t>& order, std::size_t lo, std::size_t hi, const float* points);
    void search(std::uint32_t node, double box, std::vector<double>& sides, const double* query, const float* query_f,
                double limit, std::vector<std::pair<double, std::size_t>>& out) const;

    // points a leaf scan handles at a time (a multiple of 8)
    static constexpr std::size_t kChunk = 256;
    // gaps[i] for the leaf's points [first, first + kChunk) (first a multiple
    // of kChunk), padding points included
    void scan_leaf(const Node& leaf, std::size_t first, const float* query_f, float* gaps) const;

    std::size_t stride_;
    std::size_t dims_;
    std::size_t begin_;
    std::size_t end_;
    std::size_t leaf_size_;
    std::vector<float> coords_;        // leaf blocks: dims_ rows of the leaf's points, padded to 8
    std::vector<std::uint32_t> ids_;   // their ids, in leaf order
    std::vector<Node> nodes_;
    std::vector<float> box_;  // the lowest then the highest coordinates of all points
};

}  // namespace stepstone::kb
