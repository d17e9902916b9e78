#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

namespace stepstone::kb {

/// A segment of the index and its squared distance to a query.
struct Neighbour {
    std::size_t id = 0;             ///< segment id (insertion order, from 0)
    double squared_distance = 0.0;  ///< squared_distance() to the query
};

/// Counters of the work the index did, for benchmarks and tuning.
struct IndexStats {
    std::uint64_t queries = 0;          ///< queries answered
    /// Segments whose lower bound fell within the radius (on the brute-force
    /// path only every 16th query counts them; the others add the running mean).
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
/// How: the `channels` per-channel means of a segment of `width` rows, scaled
/// by sqrt(width), form a point p; by Cauchy-Schwarz ||p(a) - p(b)|| <= ||a - b||
/// (within each channel, the sum of w squared differences is at least w times
/// the squared difference of the means). Those low-dimensional points go into
/// nanoflann KD-trees; a query fetches the segments whose lower bound is below
/// its radius and checks them in full dimension, in increasing lower-bound
/// order, stopping as soon as the bound exceeds the best distance found.
/// Lower bounds are computed in double and searched with a small safety pad,
/// so rounding can only add candidates, never lose one.
///
/// Growth: appended segments go to a short buffer scanned linearly; a full
/// buffer becomes a small tree, and trees are merged and rebuilt when a newer
/// one reaches half the size of the one before (the logarithmic method), so
/// there are O(log n) trees and each point is rebuilt O(log n) times.
///
/// When the lower bounds prune little (e.g. uniform random values), the index
/// switches to a brute-force scan (lower bound, then a full distance that stops
/// at the current bound); the switch is decided from the fraction of
/// candidates seen by recent non-const queries and never changes an answer.
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
    SegmentIndex(const SegmentIndex&) = delete;
    SegmentIndex& operator=(const SegmentIndex&) = delete;

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
    /// read once per batch rather than once per query.
    void nearest_within_batch(std::span<const float> values, const float* queries, std::size_t count,
                              double radius, std::span<std::optional<Neighbour>> out) const;
    /// As the const version, and lets the index learn whether pruning works.
    void nearest_within_batch_adaptive(std::span<const float> values, const float* queries, std::size_t count,
                                       double radius, std::span<std::optional<Neighbour>> out);

    /// Before the first adaptive query, sets the path from the fraction of
    /// segments whose lower bound lies within `radius` of `query` (so a
    /// freshly loaded index does not start on the wrong one); later a no-op.
    void probe(const float* query, double radius);

    /// True while queries use the brute-force path.
    bool brute_force() const { return brute_force_; }
    /// Work counters since construction (updated by non-const queries and
    /// growth only).
    const IndexStats& stats() const { return stats_; }
    /// Bytes the index holds per segment (lower-bound point, tree indices and nodes).
    double bytes_per_segment() const;

private:
    struct Level;
    struct Search;

    void add_point(const float* segment);
    void grow_levels();
    void rebuild_level_from(std::size_t first_level);
    void brute_batch(std::span<const float> values, const float* queries, std::size_t count, double radius,
                     std::span<std::optional<Neighbour>> out) const;
    std::size_t count_candidates(const float* query, double radius) const;
    void learn(std::size_t queries, std::size_t candidates_per_query);
    std::optional<Neighbour> search_within(std::span<const float> values, const float* query, double radius,
                                           bool brute, std::size_t* candidates) const;

    std::size_t width_;
    std::size_t channels_;
    std::size_t size_ = 0;
    // lower-bound points: channels_ doubles per segment, behind a stable
    // address because the trees' dataset adaptors point to it
    std::unique_ptr<std::vector<double>> points_;
    std::vector<std::unique_ptr<Level>> levels_;
    double max_abs_ = 0.0;
    bool brute_force_ = false;
    double candidate_fraction_ = 0.0;
    IndexStats stats_;
};

}  // namespace stepstone::kb
