#include "kb/segment_index.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include <nanoflann.hpp>

#include "core/assert.hpp"
#include "core/error.hpp"
#include "core/text.hpp"
#include "kb/distance.hpp"

namespace stepstone::kb {

namespace {

// appended segments scanned linearly before they become a tree
constexpr std::size_t kBufferSize = 64;
constexpr std::size_t kLeafSize = 16;
// relative safety pad on lower bounds, far above their rounding (~1e-15)
constexpr double kPadRelative = 1e-9;
// brute force takes over when recent queries see more than this fraction of
// the KB as candidates, and hands back below the second (hysteresis)
constexpr double kBruteAbove = 0.3;
constexpr double kTreeBelow = 0.15;
constexpr double kFractionDecay = 0.98;

// the points of one contiguous id range, as nanoflann's dataset interface
struct PointRange {
    const std::vector<double>* points = nullptr;
    std::size_t begin = 0;
    std::size_t count = 0;
    std::size_t dim = 0;

    std::size_t kdtree_get_point_count() const { return count; }
    double kdtree_get_pt(std::size_t i, std::size_t d) const { return (*points)[(begin + i) * dim + d]; }
    template <class Box>
    bool kdtree_get_bbox(Box&) const {
        return false;
    }
};

using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, PointRange, double, std::size_t>,
                                                 PointRange, -1, std::size_t>;

// a candidate: squared lower bound on its distance, and its id
using Candidate = std::pair<double, std::size_t>;

// nanoflann result set collecting every point below a squared radius, with
// ids shifted to global ids
struct Collector {
    double radius_sq;
    std::size_t offset;
    std::vector<Candidate>* out;

    std::size_t size() const { return out->size(); }
    bool full() const { return true; }
    bool addPoint(double dist_sq, std::size_t index) {
        if (dist_sq < radius_sq) out->emplace_back(dist_sq, offset + index);
        return true;
    }
    double worstDist() const { return radius_sq; }
};

// squared lower bound of a computed distance from a computed bound: the pad
// absorbs the rounding of both
double safe_lower_sq(double bound_sq, double pad) {
    const double b = std::sqrt(bound_sq) - pad;
    return b > 0 ? b * b : 0.0;
}

// the best answer so far: smallest squared distance, ties to the lowest id
struct Best {
    bool found = false;
    Neighbour n;

    void offer(std::size_t id, double d2) {
        if (!found || d2 < n.squared_distance || (d2 == n.squared_distance && id < n.id)) {
            found = true;
            n = {id, d2};
        }
    }
};

}  // namespace

struct SegmentIndex::Level {
    PointRange range;
    std::unique_ptr<Tree> tree;

    Level(const std::vector<double>* points, std::size_t begin, std::size_t end, std::size_t channels)
        : range{points, begin, end - begin, channels},
          tree(std::make_unique<Tree>(channels, range, nanoflann::KDTreeSingleIndexAdaptorParams(kLeafSize))) {}

    std::size_t begin() const { return range.begin; }
    std::size_t end() const { return range.begin + range.count; }
};

// a query's lower-bound point and the pad its magnitude requires
struct SegmentIndex::Search {
    std::vector<double> point;
    double pad = 0.0;
};

SegmentIndex::SegmentIndex(std::size_t width, std::size_t channels)
    : width_(width), channels_(channels), points_(std::make_unique<std::vector<double>>()) {
    if (width == 0) throw ConfigError("segment_width must be >= 1, got 0");
    if (channels == 0) throw ConfigError("channels must be >= 1, got 0");
}

SegmentIndex::~SegmentIndex() = default;
SegmentIndex::SegmentIndex(SegmentIndex&&) noexcept = default;
SegmentIndex& SegmentIndex::operator=(SegmentIndex&&) noexcept = default;

namespace {

// the channel means scaled by sqrt(width), written to `out`; returns the
// largest absolute value of the segment
double lower_bound_point(const float* segment, std::size_t width, std::size_t channels, double* out) {
    double max_abs = 0.0;
    for (std::size_t c = 0; c < channels; ++c) out[c] = 0.0;
    for (std::size_t t = 0; t < width; ++t) {
        const float* row = segment + t * channels;
        for (std::size_t c = 0; c < channels; ++c) {
            const double v = row[c];
            out[c] += v;
            max_abs = std::max(max_abs, std::fabs(v));
        }
    }
    const double scale = 1.0 / std::sqrt(static_cast<double>(width));
    // sum / w * sqrt(w) = sum / sqrt(w)
    for (std::size_t c = 0; c < channels; ++c) out[c] *= scale;
    return max_abs;
}

// squared distance of lower-bound points; four partial sums let it
// vectorise, and the pad covers any rounding difference
double squared_gap(const double* a, const double* b, std::size_t n) {
    double s[4] = {};
    std::size_t k = 0;
    for (; k + 4 <= n; k += 4)
        for (std::size_t j = 0; j < 4; ++j) {
            const double d = a[k + j] - b[k + j];
            s[j] += d * d;
        }
    for (std::size_t j = 0; k < n; ++k, ++j) {
        const double d = a[k] - b[k];
        s[j] += d * d;
    }
    return (s[0] + s[1]) + (s[2] + s[3]);
}

// values covered by the single-precision prefilter of the brute-force path
constexpr std::size_t kPrefilterValues = 32;
// above this magnitude float squares could overflow: no prefilter
constexpr double kPrefilterMaxAbs = 1e15;

// sum of squared differences of the first values in float, eight lanes; a
// rejection test only: it is within 35 float ulps (relative) of the true
// partial sum, which never exceeds the full distance
float prefix_gap(const float* a, const float* b) {
    static_assert(kPrefilterValues % 8 == 0);
    float s[8] = {};
    for (std::size_t k = 0; k < kPrefilterValues; k += 8)
        for (std::size_t j = 0; j < 8; ++j) {
            const float d = a[k + j] - b[k + j];
            s[j] += d * d;
        }
    return ((s[0] + s[1]) + (s[2] + s[3])) + ((s[4] + s[5]) + (s[6] + s[7]));
}

// true if the prefix sum proves the computed double distance exceeds bound
bool prefix_exceeds(float prefix, double bound) {
    return static_cast<double>(prefix) > bound * (1.0 + 1e-5) + 1e-30;
}

}  // namespace

void SegmentIndex::add_point(const float* segment) {
    std::vector<double>& points = *points_;
    points.resize(points.size() + channels_);
    const double max_abs = lower_bound_point(segment, width_, channels_, points.data() + size_ * channels_);
    max_abs_ = std::max(max_abs_, max_abs);
    ++size_;
}

void SegmentIndex::append(const float* segment) {
    add_point(segment);
    grow_levels();
}

void SegmentIndex::assign(std::span<const float> values) {
    STEPSTONE_ASSERT(values.size() % dim() == 0);
    const std::size_t count = values.size() / dim();
    levels_.clear();
    points_->clear();
    points_->reserve(count * channels_);
    size_ = 0;
    max_abs_ = 0.0;
    for (std::size_t i = 0; i < count; ++i) add_point(values.data() + i * dim());
    if (count > 0) {
        levels_.push_back(std::make_unique<Level>(points_.get(), 0, count, channels_));
        ++stats_.rebuilds;
        stats_.rebuilt_points += count;
    }
}

void SegmentIndex::grow_levels() {
    const std::size_t indexed = levels_.empty() ? 0 : levels_.back()->end();
    if (size_ - indexed < kBufferSize) return;
    // the buffer becomes a level; absorb the previous levels while the new
    // one is at least half their size, then build a single tree
    std::size_t begin = indexed;
    while (!levels_.empty() && 2 * (size_ - begin) >= levels_.back()->range.count) {
        begin = levels_.back()->begin();
        levels_.pop_back();
    }
    levels_.push_back(std::make_unique<Level>(points_.get(), begin, size_, channels_));
    ++stats_.rebuilds;
    stats_.rebuilt_points += size_ - begin;
}

double SegmentIndex::bytes_per_segment() const {
    // lower-bound point, nanoflann's index permutation, about two nodes per leaf
    constexpr double kNodeBytes = 48.0;
    return static_cast<double>(channels_ * sizeof(double) + sizeof(std::size_t)) + 2.0 * kNodeBytes / kLeafSize;
}

std::optional<Neighbour> SegmentIndex::search_within(std::span<const float> values, const float* query,
                                                     double radius, bool brute,
                                                     std::size_t* candidates) const {
    STEPSTONE_ASSERT(values.size() >= size_ * dim());
    const std::size_t n_dim = dim();
    std::vector<double> q(channels_);
    const double q_abs = lower_bound_point(query, width_, channels_, q.data());
    const double pad = kPadRelative * (1.0 + std::max(max_abs_, q_abs)) * std::sqrt(static_cast<double>(n_dim));
    const double radius_sq = radius * radius;
    const double search_sq = (radius + pad) * (radius + pad);
    const double* points = points_->data();
    Best best;

    if (brute) {
        // id order, so a later segment at an equal distance never wins; a
        // float sum over the first values rejects most segments cheaply, and
        // lower bounds are counted on a sample of queries only (to notice
        // when pruning works again)
        const bool prefilter = std::max(max_abs_, q_abs) < kPrefilterMaxAbs && n_dim > kPrefilterValues;
        const bool count = candidates != nullptr && stats_.queries % 16 == 0;
        std::size_t seen = 0;
        for (std::size_t id = 0; id < size_; ++id) {
            if (count && squared_gap(q.data(), points + id * channels_, channels_) < search_sq) ++seen;
            const double bound = best.found ? best.n.squared_distance : radius_sq;
            const float* s = values.data() + id * n_dim;
            if (prefilter && prefix_exceeds(prefix_gap(query, s), bound)) continue;
            const double d2 = squared_distance_up_to(query, s, n_dim, bound);
            if (d2 < radius_sq) best.offer(id, d2);
        }
        if (candidates) *candidates = count ? seen : static_cast<std::size_t>(candidate_fraction_ * static_cast<double>(size_));
    } else {
        // candidates from every tree and from the buffer
        std::vector<Candidate> found;
        nanoflann::SearchParams params(32, 0.0f, false);
        for (const auto& level : levels_) {
            Collector collector{search_sq, level->begin(), &found};
            level->tree->findNeighbors(collector, q.data(), params);
        }
        const std::size_t indexed = levels_.empty() ? 0 : levels_.back()->end();
        for (std::size_t id = indexed; id < size_; ++id) {
            const double lb = squared_gap(q.data(), points + id * channels_, channels_);
            if (lb < search_sq) found.emplace_back(lb, id);
        }
        if (candidates) *candidates = found.size();

        // exact checks in increasing lower bound; stop once the bound passes the best
        for (auto& c : found) c.first = safe_lower_sq(c.first, pad);
        std::sort(found.begin(), found.end());
        for (const auto& [lower, id] : found) {
            const double bound = best.found ? best.n.squared_distance : radius_sq;
            if (lower > bound) break;
            const double d2 = squared_distance_up_to(query, values.data() + id * n_dim, n_dim, bound);
            if (d2 < radius_sq) best.offer(id, d2);
        }
    }
    if (!best.found) return std::nullopt;
    return best.n;
}

std::optional<Neighbour> SegmentIndex::nearest_within(std::span<const float> values, const float* query,
                                                      double radius) const {
    return search_within(values, query, radius, brute_force_, nullptr);
}

std::size_t SegmentIndex::count_candidates(const float* query, double radius) const {
    std::vector<double> q(channels_);
    const double q_abs = lower_bound_point(query, width_, channels_, q.data());
    const double pad = kPadRelative * (1.0 + std::max(max_abs_, q_abs)) * std::sqrt(static_cast<double>(dim()));
    const double search_sq = (radius + pad) * (radius + pad);
    std::size_t seen = 0;
    for (std::size_t id = 0; id < size_; ++id)
        if (squared_gap(q.data(), points_->data() + id * channels_, channels_) < search_sq) ++seen;
    return seen;
}

void SegmentIndex::probe(const float* query, double radius) {
    if (stats_.queries > 0 || size_ == 0) return;
    candidate_fraction_ = static_cast<double>(count_candidates(query, radius)) / static_cast<double>(size_);
    brute_force_ = candidate_fraction_ > kBruteAbove;
}

void SegmentIndex::learn(std::size_t queries, std::size_t candidates_per_query) {
    stats_.queries += queries;
    stats_.candidates += queries * candidates_per_query;
    if (brute_force_) stats_.linear_queries += queries;
    if (size_ == 0 || queries == 0) return;
    const double fraction = static_cast<double>(candidates_per_query) / static_cast<double>(size_);
    const double keep = std::pow(kFractionDecay, static_cast<double>(queries));
    candidate_fraction_ = keep * candidate_fraction_ + (1.0 - keep) * fraction;
    if (!brute_force_ && candidate_fraction_ > kBruteAbove) brute_force_ = true;
    if (brute_force_ && candidate_fraction_ < kTreeBelow) brute_force_ = false;
}

void SegmentIndex::brute_batch(std::span<const float> values, const float* queries, std::size_t count,
                               double radius, std::span<std::optional<Neighbour>> out) const {
    const std::size_t n_dim = dim();
    const double radius_sq = radius * radius;
    double q_abs = 0.0;
    for (std::size_t k = 0; k < count * n_dim; ++k) q_abs = std::max(q_abs, static_cast<double>(std::fabs(queries[k])));
    const bool prefilter = std::max(max_abs_, q_abs) < kPrefilterMaxAbs && n_dim > kPrefilterValues;
    std::vector<Best> best(count);

    // blocks of segments small enough to stay in the first-level cache while
    // every query passes over them; ids ascend within each query's scan
    constexpr std::size_t kBlockBytes = 64 * 1024;
    const std::size_t block = std::max<std::size_t>(1, kBlockBytes / (n_dim * sizeof(float)));
    for (std::size_t j0 = 0; j0 < size_; j0 += block) {
        const std::size_t j1 = std::min(size_, j0 + block);
        for (std::size_t i = 0; i < count; ++i) {
            const float* q = queries + i * n_dim;
            Best& b = best[i];
            for (std::size_t id = j0; id < j1; ++id) {
                const double bound = b.found ? b.n.squared_distance : radius_sq;
                const float* s = values.data() + id * n_dim;
                if (prefilter && prefix_exceeds(prefix_gap(q, s), bound)) continue;
                const double d2 = squared_distance_up_to(q, s, n_dim, bound);
                if (d2 < radius_sq) b.offer(id, d2);
            }
        }
    }
    for (std::size_t i = 0; i < count; ++i) out[i] = best[i].found ? std::optional<Neighbour>(best[i].n) : std::nullopt;
}

void SegmentIndex::nearest_within_batch(std::span<const float> values, const float* queries, std::size_t count,
                                        double radius, std::span<std::optional<Neighbour>> out) const {
    STEPSTONE_ASSERT(out.size() >= count);
    if (brute_force_) {
        brute_batch(values, queries, count, radius, out);
        return;
    }
    for (std::size_t i = 0; i < count; ++i) out[i] = search_within(values, queries + i * dim(), radius, false, nullptr);
}

void SegmentIndex::nearest_within_batch_adaptive(std::span<const float> values, const float* queries,
                                                 std::size_t count, double radius,
                                                 std::span<std::optional<Neighbour>> out) {
    STEPSTONE_ASSERT(out.size() >= count);
    if (count == 0) return;
    if (!brute_force_) {
        for (std::size_t i = 0; i < count; ++i) out[i] = nearest_within_adaptive(values, queries + i * dim(), radius);
        return;
    }
    // the first query's lower bounds stand for the batch's pruning
    const std::size_t seen = count_candidates(queries, radius);
    brute_batch(values, queries, count, radius, out);
    learn(count, seen);
}

std::optional<Neighbour> SegmentIndex::nearest_within_adaptive(std::span<const float> values,
                                                               const float* query, double radius) {
    std::size_t seen = 0;
    auto result = search_within(values, query, radius, brute_force_, &seen);

    // learn whether the lower bounds prune on this data
    learn(1, seen);
    return result;
}

std::optional<Neighbour> SegmentIndex::nearest(std::span<const float> values, const float* query) const {
    if (size_ == 0) return std::nullopt;
    const std::size_t n_dim = dim();

    // an upper bound: the exact distance of the lower-bound nearest of each
    // tree, and of the first buffered segment
    Best best;
    std::vector<double> q(channels_);
    lower_bound_point(query, width_, channels_, q.data());
    for (const auto& level : levels_) {
        std::size_t local = 0;
        double lb = 0.0;
        nanoflann::KNNResultSet<double, std::size_t> result(1);
        result.init(&local, &lb);
        level->tree->findNeighbors(result, q.data(), nanoflann::SearchParams());
        const std::size_t id = level->begin() + local;
        best.offer(id, squared_distance(query, values.data() + id * n_dim, n_dim));
    }
    const std::size_t indexed = levels_.empty() ? 0 : levels_.back()->end();
    if (indexed < size_) best.offer(indexed, squared_distance(query, values.data() + indexed * n_dim, n_dim));
    STEPSTONE_ASSERT(best.found);

    // every segment at most that far is within a radius whose square exceeds it
    double radius = std::max(std::sqrt(best.n.squared_distance), 1e-150);
    while (!(radius * radius > best.n.squared_distance)) radius = std::nextafter(radius, HUGE_VAL);
    if (!std::isfinite(radius)) {
        // distances beyond double range: compare every segment
        Best all;
        for (std::size_t id = 0; id < size_; ++id)
            all.offer(id, squared_distance(query, values.data() + id * n_dim, n_dim));
        return all.n;
    }
    auto within = search_within(values, query, radius, brute_force_, nullptr);
    STEPSTONE_ASSERT(within.has_value());
    return within;
}

}  // namespace stepstone::kb
