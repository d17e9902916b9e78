#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "kb/detail/huge_pages.hpp"

namespace stepstone::kb {

class BlockMeans;
class Projection;

/// A segment of the index and its squared distance to a query.
struct Neighbour {
    std::size_t id = 0;             ///< segment id (insertion order, from 0)
    double squared_distance = 0.0;  ///< squared_distance() to the query
};

/// A radius whose square exceeds `squared_distance` (>= 0), as small as
/// stepping up from its square root allows: a search within it finds every
/// segment at most that far. Infinite when the square root is near the top
/// of double's range.
double radius_covering(double squared_distance);

/// Counters of the work the index did, for benchmarks and tuning.
struct IndexStats {
    std::uint64_t queries = 0;          ///< queries answered
    /// Segments whose projected lower bound passed the search limit (the
    /// radius, shrinking to the bound of the best match found so far) in the
    /// trees and the buffer (on the brute-force path only every 16th query
    /// counts them against the radius; the others add the running mean).
    std::uint64_t candidates = 0;
    std::uint64_t linear_queries = 0;   ///< queries answered by the brute-force path
    std::uint64_t rebuilds = 0;         ///< KD-trees built
    std::uint64_t rebuilt_points = 0;   ///< points put into those trees
};

/// Exact nearest-segment search over the segments of one knowledge base.
///
/// Every answer equals a linear scan's under squared_distance(): the nearest
/// segment is the one with the smallest squared distance, ties going to the
/// lowest id, and "within r" means squared distance < r * r.
///
/// How: the block means of a segment (BlockMeans: 5 row blocks x channels,
/// each mean scaled by sqrt(rows)) bound its distance from below by
/// Cauchy-Schwarz; a projection with orthonormal rows (the leading principal
/// directions of the indexed block means, or the channel means while the index
/// is small) keeps a lower bound in a few dimensions. The projected points go
/// into KD-trees (BoundTree) whose nodes keep tight bounding boxes; a query
/// walks each tree depth first, nearer box first, and checks every segment
/// whose projected bound passes against its block-means bound and then in full
/// dimension; each match shrinks the search limit to the bound of the best
/// distance found, so the rest of the walk prunes more. Bounds are kept in
/// float with a safety pad (and a relative slack for float sums), so rounding
/// can only add candidates, never lose one.
///
/// Growth: appended segments go to a short buffer scanned linearly; a full
/// buffer becomes a small tree, and trees are merged and rebuilt when a newer
/// one reaches half the size of the one before (the logarithmic method), so
/// there are O(log n) trees and each point is rebuilt O(log n) times. The
/// projection is refitted when everything is rebuilt and the index has doubled
/// since the last fit.
///
/// When the lower bounds prune little (e.g. uniform random values), the index
/// switches to a brute-force scan (lower bound, then a full distance that stops
/// at the current bound); the switch is decided from the fraction of
/// candidates seen by recent non-const queries and never changes an answer.
/// Values so large that float bounds could overflow (|value| x sqrt(width) >=
/// 1e15) also send every query to the brute-force scan.
///
/// The index stores no segment values: queries take the values of all indexed
/// segments (segment i at values[i * dim, (i + 1) * dim)), which must be the
/// ones appended, in the same order. Const queries can run concurrently.
class SegmentIndex {
public:
    /// An empty index for segments of `width` rows of `channels` values.
    /// Throws ConfigError if width or channels is 0.
    SegmentIndex(std::size_t width, std::size_t channels);
    ~SegmentIndex();
    SegmentIndex(SegmentIndex&&) noexcept;
    SegmentIndex& operator=(SegmentIndex&&) noexcept;
    /// A deep copy (trees, bound points, projection, path and counters).
    SegmentIndex(const SegmentIndex& other);
    SegmentIndex& operator=(const SegmentIndex& other);

    /// Values per segment (width x channels).
    std::size_t dim() const { return width_ * channels_; }
    /// Number of indexed segments.
    std::size_t size() const { return size_; }

    /// Indexes one more segment (id = size()); `segment` holds dim() values.
    void append(const float* segment);
    /// Replaces the content by the `count` segments of `values` and builds one
    /// tree over all of them (used when loading a knowledge base).
    void assign(std::span<const float> values);

    /// The nearest segment with squared distance < radius * radius (ties: lowest
    /// id), or nullopt. `values` holds the indexed segments, `query` dim() values.
    std::optional<Neighbour> nearest_within(std::span<const float> values, const float* query,
                                            double radius) const;
    /// As the const version, and lets the index learn whether pruning works on
    /// this data (switching between tree and brute-force search).
    std::optional<Neighbour> nearest_within_adaptive(std::span<const float> values, const float* query,
                                                     double radius);
    /// The nearest segment whatever its distance (ties: lowest id), or nullopt
    /// if the index is empty.
    std::optional<Neighbour> nearest(std::span<const float> values, const float* query) const;

    /// nearest_within() for `count` queries (query i at queries + i * dim())
    /// against the current content, written to out[0, count). On the
    /// brute-force path the scan is blocked so that each indexed segment is
    /// read once per batch rather than once per query. Throws DataError
    /// naming the first query with a NaN or infinite value and its position
    /// (as kb::require_finite), `out` then being unspecified: the queries need
    /// not be checked beforehand.
    void nearest_within_batch(std::span<const float> values, const float* queries, std::size_t count,
                              double radius, std::span<std::optional<Neighbour>> out) const;
    /// As the const version, and lets the index learn whether pruning works.
    void nearest_within_batch_adaptive(std::span<const float> values, const float* queries, std::size_t count,
                                       double radius, std::span<std::optional<Neighbour>> out);

    /// Before the first adaptive query, sets the path from the fraction of
    /// segments whose lower bound lies within `radius` of `query` (so a
    /// freshly loaded index does not start on the wrong one); later a no-op.
    void probe(const float* query, double radius);

    /// The fraction of indexed segments whose lower bound lies within
    /// `radius` of `query` (what a search would check in full); 0 when empty.
    double candidate_fraction(const float* query, double radius) const;

    /// True while queries use the brute-force path.
    bool brute_force() const { return brute_force_ || huge_; }
    /// Work counters since construction (updated by non-const queries and
    /// growth only).
    const IndexStats& stats() const { return stats_; }
    /// Bytes the index holds per segment (bound points, tree copies, ids and nodes).
    double bytes_per_segment() const;

private:
    struct Level;
    struct Search;
    struct Turn;
    struct Best;

    std::size_t tree_stride() const;
    std::size_t filter_dim() const;
    void project(std::size_t id);
    void choose_projection();
    Search prepare(const float* query) const;
    void prepare(const float* query, Search& search) const;
    bool passes_filter(const Search& q, std::size_t id, double limit) const;
    void check(std::span<const float> values, const float* query, const Search& q, double radius_sq, std::size_t id,
               Best& best, double& limit) const;
    template <class Visit>
    void scan_buffer(const Search& q, const double& limit, Visit&& visit) const;
    void tree_batch(std::span<const float> values, const float* queries, std::size_t count, double radius,
                    std::span<std::optional<Neighbour>> out) const;
    void add_point(const float* segment);
    void grow_levels();
    void brute_batch(std::span<const float> values, const float* queries, std::size_t count, double radius,
                     std::span<std::optional<Neighbour>> out) const;
    std::size_t count_candidates(const float* query, double radius) const;
    void learn(std::size_t queries, std::size_t candidates_per_query);
    std::optional<Neighbour> search_within(std::span<const float> values, const float* query, double radius,
                                           bool brute, std::size_t* candidates) const;

    std::size_t width_;
    std::size_t channels_;
    std::size_t size_ = 0;
    std::unique_ptr<BlockMeans> fine_;
    std::unique_ptr<Projection> projection_;
    std::size_t principal_size_ = 0;  // size when the projection was fitted (0: channel means)
    bool filter_on_ = false;
    bool huge_ = false;  // values too large for the float points: brute force only
    std::vector<double> scratch_;  // one point while appending
    // tree points: tree_stride() floats per segment (projected filter points)
    detail::HugeVector<float> tree_points_;
    // filter points: filter_dim() floats per segment (block means)
    detail::HugeVector<float> filter_points_;
    std::vector<std::unique_ptr<Level>> levels_;
    double max_abs_ = 0.0;
    bool brute_force_ = false;
    double candidate_fraction_ = 0.0;
    IndexStats stats_;
};

}  // namespace stepstone::kb
