#include "kb/segment_index.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "core/assert.hpp"
#include "core/error.hpp"
#include "core/text.hpp"
#include "kb/block_means.hpp"
#include "kb/bound_tree.hpp"
#include "kb/detail/prefetch.hpp"
#include "kb/distance.hpp"
#include "kb/projection.hpp"
#include "kb/segments.hpp"

namespace stepstone::kb {

namespace {

// appended segments scanned linearly before they become a tree
constexpr std::size_t kBufferSize = 64;
constexpr std::size_t kLeafSize = 16;
// row blocks of the finer bound that filters the tree's candidates, and
// dimension of the tree's points (its leading principal directions)
constexpr std::size_t kFilterBlocks = 5;
constexpr std::size_t kTreeDim = 20;
// the principal directions are fitted once the index holds this many segments
constexpr std::size_t kMinPrincipal = 1024;
// relative safety pad on lower bounds: rounding a block-means point (or its
// projection) to float moves it by at most 2^-24 x max|value| x sqrt(dim);
// a stored tree point is rounded twice and the query's float point once, so
// 2^-21 leaves a factor 8/3 (the double arithmetic adds ~1e-13)
constexpr double kPadRelative = 0x1p-21;
// a float sum of n squares is within a relative (n + 2) x 2^-24 of the exact
// one; bounds are compared with twice that for the longest sum, plus 2^-20
constexpr double kSumSlackPerTerm = 0x1p-23;
// the float points and sums are used while they cannot overflow
constexpr double kMaxCoordinate = 1e15;
constexpr std::size_t kFilterMaxDim = 512;
// brute force takes over when recent queries see more than this fraction of
// the KB as candidates, and hands back below the second (hysteresis)
constexpr double kBruteAbove = 0.1;
constexpr double kTreeBelow = 0.05;
constexpr double kFractionDecay = 0.98;

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

double radius_covering(double squared_distance) {
    double radius = std::max(std::sqrt(squared_distance), 1e-150);
    while (!(radius * radius > squared_distance) && std::isfinite(radius))
        radius = std::nextafter(radius, HUGE_VAL);
    return radius;
}

// the best answer so far: smallest squared distance, ties to the lowest id
struct SegmentIndex::Best {
    bool found = false;
    Neighbour n;

    void offer(std::size_t id, double d2) {
        if (!found || d2 < n.squared_distance || (d2 == n.squared_distance && id < n.id)) {
            found = true;
            n = {id, d2};
        }
    }
};

struct SegmentIndex::Level {
    BoundTree tree;
    std::size_t begin() const { return tree.begin(); }
    std::size_t end() const { return tree.end(); }
    std::size_t count() const { return tree.size(); }
};

// a query's lower-bound points and the pads their magnitude requires
struct SegmentIndex::Search {
    std::vector<double> fine;         // block-means point
    std::vector<double> point;        // tree point, padded to tree_stride()
    std::vector<float> point_f;       // the same in float
    std::vector<float> filter_point;  // empty when the filter is off for this query
    double max_abs = 0.0;  // largest |value| of the query and the indexed segments
    bool finite = true;    // false when the query holds a NaN or an infinity
    double pad = 0.0;
    double slack = 0.0;    // relative slack for float sums

    // largest key (tree bound or filter sum) a segment at squared distance
    // <= bound can have
    double key_limit(double bound) const {
        const double root = std::sqrt(bound);
        return (1.0 + slack) * (root + pad) * (root + pad) + 1e-30;
    }
};

SegmentIndex::SegmentIndex(std::size_t width, std::size_t channels) : width_(width), channels_(channels) {
    if (width == 0) throw ConfigError("segment_width must be >= 1, got 0");
    if (channels == 0) throw ConfigError("channels must be >= 1, got 0");
    fine_ = std::make_unique<BlockMeans>(width_, channels_, kFilterBlocks);
    projection_ = std::make_unique<Projection>(Projection::channel_means(width_, channels_, fine_->blocks()));
    filter_on_ = fine_->dim() < dim() && fine_->dim() <= kFilterMaxDim;
}

SegmentIndex::~SegmentIndex() = default;
SegmentIndex::SegmentIndex(SegmentIndex&&) noexcept = default;

SegmentIndex::SegmentIndex(const SegmentIndex& other)
    : width_(other.width_),
      channels_(other.channels_),
      size_(other.size_),
      fine_(std::make_unique<BlockMeans>(*other.fine_)),
      projection_(std::make_unique<Projection>(*other.projection_)),
      principal_size_(other.principal_size_),
      filter_on_(other.filter_on_),
      huge_(other.huge_),
      tree_points_(other.tree_points_),
      filter_points_(other.filter_points_),
      max_abs_(other.max_abs_),
      brute_force_(other.brute_force_),
      candidate_fraction_(other.candidate_fraction_),
      stats_(other.stats_) {
    levels_.reserve(other.levels_.size());
    for (const auto& level : other.levels_) levels_.push_back(std::make_unique<Level>(*level));
}

SegmentIndex& SegmentIndex::operator=(const SegmentIndex& other) {
    if (this != &other) {
        SegmentIndex copy(other);
        *this = std::move(copy);
    }
    return *this;
}
SegmentIndex& SegmentIndex::operator=(SegmentIndex&&) noexcept = default;

std::size_t SegmentIndex::tree_stride() const { return (projection_->out_dim() + 7) / 8 * 8; }
std::size_t SegmentIndex::filter_dim() const { return fine_->dim(); }

void SegmentIndex::project(std::size_t id) {
    const std::size_t stride = tree_stride();
    scratch_.assign(stride, 0.0);
    projection_->apply(filter_points_.data() + id * filter_dim(), scratch_.data());
    for (std::size_t d = 0; d < stride; ++d) tree_points_[id * stride + d] = static_cast<float>(scratch_[d]);
}

void SegmentIndex::add_point(const float* segment) {
    scratch_.resize(filter_dim());
    const double max_abs = fine_->point(segment, scratch_.data());
    max_abs_ = std::max(max_abs_, max_abs);
    // beyond this magnitude the float points could overflow: brute force only
    if (max_abs_ * std::sqrt(static_cast<double>(width_)) >= kMaxCoordinate) huge_ = true;
    for (const double v : scratch_) filter_points_.push_back(static_cast<float>(v));
    tree_points_.resize(tree_points_.size() + tree_stride());
    ++size_;
}

void SegmentIndex::choose_projection() {
    if (size_ >= kMinPrincipal && !huge_) {
        const std::size_t f_dim = filter_dim();
        *projection_ = Projection::principal(filter_points_.data(), size_, f_dim, std::min(kTreeDim, f_dim),
                                             Projection::channel_means(width_, channels_, fine_->blocks()));
        principal_size_ = size_;
    }
    tree_points_.assign(size_ * tree_stride(), 0.0f);
    for (std::size_t id = 0; id < size_; ++id) project(id);
}

SegmentIndex::Search SegmentIndex::prepare(const float* query) const {
    Search search;
    prepare(query, search);
    return search;
}

void SegmentIndex::prepare(const float* query, Search& search) const {
    search.fine.resize(filter_dim());
    const double q_abs = fine_->point(query, search.fine.data());
    search.finite = q_abs <= std::numeric_limits<double>::max();
    const double max_abs = std::max(max_abs_, q_abs);
    search.max_abs = max_abs;
    search.point.assign(tree_stride(), 0.0);
    projection_->apply(search.fine.data(), search.point.data());
    search.point_f.assign(search.point.begin(), search.point.end());
    search.pad = kPadRelative * (1.0 + max_abs) * std::sqrt(static_cast<double>(dim()));
    const std::size_t terms = std::max(tree_stride(), filter_dim()) + 8;
    search.slack = kSumSlackPerTerm * static_cast<double>(terms) + 0x1p-20;
    if (filter_on_) {
        search.filter_point.assign(search.fine.begin(), search.fine.end());
    } else {
        search.filter_point.clear();
    }
}

void SegmentIndex::append(const float* segment) {
    add_point(segment);
    project(size_ - 1);
    grow_levels();
}

void SegmentIndex::assign(std::span<const float> values) {
    STEPSTONE_ASSERT(values.size() % dim() == 0);
    const std::size_t count = values.size() / dim();
    levels_.clear();
    *projection_ = Projection::channel_means(width_, channels_, fine_->blocks());
    principal_size_ = 0;
    tree_points_.clear();
    tree_points_.reserve(count * tree_stride());
    filter_points_.clear();
    filter_points_.reserve(count * filter_dim());
    size_ = 0;
    max_abs_ = 0.0;
    huge_ = false;
    for (std::size_t i = 0; i < count; ++i) add_point(values.data() + i * dim());
    choose_projection();
    if (count > 0) {
        levels_.push_back(std::make_unique<Level>(
            Level{BoundTree(tree_points_.data(), tree_stride(), projection_->out_dim(), 0, count, kLeafSize)}));
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
    while (!levels_.empty() && 2 * (size_ - begin) >= levels_.back()->count()) {
        begin = levels_.back()->begin();
        levels_.pop_back();
    }
    // a rebuild of everything may first fit the projection to the data
    if (begin == 0 && size_ >= kMinPrincipal && size_ >= 2 * principal_size_) choose_projection();
    levels_.push_back(std::make_unique<Level>(
        Level{BoundTree(tree_points_.data(), tree_stride(), projection_->out_dim(), begin, size_, kLeafSize)}));
    ++stats_.rebuilds;
    stats_.rebuilt_points += size_ - begin;
}

double SegmentIndex::bytes_per_segment() const {
    // filter and tree points, plus each level's copy of its points, ids and nodes
    double bytes = static_cast<double>(tree_stride() * sizeof(float) + (filter_on_ ? filter_dim() * sizeof(float) : 0));
    for (const auto& level : levels_)
        bytes += level->tree.bytes_per_point() * static_cast<double>(level->count()) / static_cast<double>(size_);
    return bytes;
}

bool SegmentIndex::passes_filter(const Search& q, std::size_t id, double limit) const {
    if (q.filter_point.empty()) return true;
    const std::size_t f_dim = filter_dim();
    return static_cast<double>(squared_gap(q.filter_point.data(), filter_points_.data() + id * f_dim, f_dim)) <= limit;
}

void SegmentIndex::check(std::span<const float> values, const float* query, const Search& q, double radius_sq,
                         std::size_t id, Best& best, double& limit) const {
    const std::size_t n_dim = dim();
    const double bound = best.found ? best.n.squared_distance : radius_sq;
    const double d2 = squared_distance_up_to(query, values.data() + id * n_dim, n_dim, bound);
    if (d2 < radius_sq) {
        best.offer(id, d2);
        limit = q.key_limit(best.n.squared_distance);
    }
}

// `limit` is read afresh for each segment: `visit` may shrink it
template <class Visit>
void SegmentIndex::scan_buffer(const Search& q, const double& limit, Visit&& visit) const {
    const std::size_t stride = tree_stride();
    const std::size_t indexed = levels_.empty() ? 0 : levels_.back()->end();
    for (std::size_t id = indexed; id < size_; ++id) {
        const float gap = squared_gap(q.point_f.data(), tree_points_.data() + id * stride, stride);
        if (static_cast<double>(gap) <= limit) visit(id);
    }
}

// one query of tree_batch(): its walk through the trees and the candidates
// waiting for their data to arrive
struct SegmentIndex::Turn {
    std::size_t query = 0;  // index in the batch
    Search q;
    Best best;
    double limit = 0.0;
    std::size_t level = 0;
    BoundTree::Walk walk;
    std::vector<BoundTree::Found> found;  // tree candidates, filter points loading
    std::vector<std::uint32_t> close;     // past the filter, values loading
};

void SegmentIndex::tree_batch(std::span<const float> values, const float* queries, std::size_t count,
                              double radius, std::span<std::optional<Neighbour>> out) const {
    // a walk through the trees is a chain of dependent loads (a node's
    // children are known once it is read); several queries take turns, one
    // step each, and every step prefetches what its walk's next step reads,
    // so that the loads of one walk overlap the work of the others. Each
    // query's answer is the one search_within() gives: its nodes are visited
    // in the same order, only the checks of a leaf's candidates come a turn
    // or two later (with the limit of that time)
    const std::size_t n_dim = dim();
    const std::size_t f_dim = filter_dim();
    const double radius_sq = radius * radius;
    constexpr std::size_t kTurns = 4;
    std::vector<std::unique_ptr<Turn>> turns;
    std::size_t next = 0;
    const auto begin_query = [&](Turn& t) {
        t.query = next++;
        // the query that starts next is read in full then: start loading it
        if (next < count) detail::prefetch(queries + next * n_dim, n_dim * sizeof(float));
        prepare(queries + t.query * n_dim, t.q);
        // queries start in order, so the first one refused is the first
        // with a non-finite value
        if (!t.q.finite) require_finite(std::span<const float>(queries + t.query * n_dim, n_dim), n_dim, t.query);
        t.best = Best{};
        t.limit = t.q.key_limit(radius_sq);
        t.level = 0;
        t.walk.start(levels_[0]->tree, t.q.point_f.data(), t.limit);
    };
    for (std::size_t i = 0; i < std::min(kTurns, count); ++i) {
        turns.push_back(std::make_unique<Turn>());
        begin_query(*turns.back());
    }
    std::size_t running = turns.size();
    while (running > 0) {
        for (auto& slot : turns) {
            if (!slot) continue;
            Turn& t = *slot;
            const float* query = queries + t.query * n_dim;
            if (!t.close.empty()) {
                for (const std::uint32_t id : t.close) check(values, query, t.q, radius_sq, id, t.best, t.limit);
                t.close.clear();
            } else if (!t.found.empty()) {
                for (const BoundTree::Found& f : t.found) {
                    if (static_cast<double>(f.gap) > t.limit) continue;
                    if (!passes_filter(t.q, f.id, t.limit)) continue;
                    t.close.push_back(f.id);
                    detail::prefetch(values.data() + std::size_t{f.id} * n_dim, n_dim * sizeof(float));
                }
                t.found.clear();
            } else if (!t.walk.done()) {
                t.walk.step(t.limit, t.found);
                if (!t.q.filter_point.empty())
                    for (const BoundTree::Found& f : t.found)
                        detail::prefetch(filter_points_.data() + std::size_t{f.id} * f_dim, f_dim * sizeof(float));
            } else if (t.level + 1 < levels_.size()) {
                t.walk.start(levels_[++t.level]->tree, t.q.point_f.data(), t.limit);
            } else {
                scan_buffer(t.q, t.limit, [&](std::size_t id) {
                    if (passes_filter(t.q, id, t.limit)) check(values, query, t.q, radius_sq, id, t.best, t.limit);
                });
                out[t.query] = t.best.found ? std::optional<Neighbour>(t.best.n) : std::nullopt;
                if (next < count) {
                    begin_query(t);
                } else {
                    slot.reset();
                    --running;
                }
            }
        }
    }
}

std::optional<Neighbour> SegmentIndex::search_within(std::span<const float> values, const float* query,
                                                     double radius, bool brute,
                                                     std::size_t* candidates) const {
    STEPSTONE_ASSERT(values.size() >= size_ * dim());
    const std::size_t n_dim = dim();
    const std::size_t stride = tree_stride();
    const Search q = prepare(query);
    const double radius_sq = radius * radius;
    const double search_limit = q.key_limit(radius_sq);
    Best best;

    if (brute || huge_) {
        // id order, so a later segment at an equal distance never wins; a
        // float sum over the first values rejects most segments cheaply, and
        // lower bounds are counted on a sample of queries only (to notice
        // when pruning works again)
        const bool prefilter = q.max_abs < kPrefilterMaxAbs && n_dim > kPrefilterValues;
        const bool count = candidates != nullptr && stats_.queries % 16 == 0 && !huge_;
        std::size_t seen = 0;
        for (std::size_t id = 0; id < size_; ++id) {
            if (count && squared_gap(q.point_f.data(), tree_points_.data() + id * stride, stride) <= search_limit) ++seen;
            const double bound = best.found ? best.n.squared_distance : radius_sq;
            const float* s = values.data() + id * n_dim;
            if (prefilter && prefix_exceeds(prefix_gap(query, s), bound)) continue;
            const double d2 = squared_distance_up_to(query, s, n_dim, bound);
            if (d2 < radius_sq) best.offer(id, d2);
        }
        if (candidates) *candidates = count ? seen : static_cast<std::size_t>(candidate_fraction_ * static_cast<double>(size_));
    } else {
        // every tree, then the buffer: a segment whose projected bound passes
        // is checked at once against its block-means bound and then in full,
        // and each match shrinks the limit to the bound of the best distance
        // found so far (a segment at an equal distance still passes: ties go
        // to the lowest id)
        double limit = search_limit;
        std::size_t seen = 0;
        const auto visit = [&](std::size_t id) {
            ++seen;
            if (!passes_filter(q, id, limit)) return limit;
            check(values, query, q, radius_sq, id, best, limit);
            return limit;
        };
        for (const auto& level : levels_) level->tree.search(q.point_f.data(), limit, visit);
        scan_buffer(q, limit, visit);
        if (candidates) *candidates = seen;
    }
    if (!best.found) return std::nullopt;
    return best.n;
}

std::optional<Neighbour> SegmentIndex::nearest_within(std::span<const float> values, const float* query,
                                                      double radius) const {
    return search_within(values, query, radius, brute_force_, nullptr);
}

std::size_t SegmentIndex::count_candidates(const float* query, double radius) const {
    if (huge_) return size_;
    const Search q = prepare(query);
    const double limit = q.key_limit(radius * radius);
    const std::size_t stride = tree_stride();
    std::size_t seen = 0;
    for (std::size_t id = 0; id < size_; ++id)
        if (squared_gap(q.point_f.data(), tree_points_.data() + id * stride, stride) <= limit) ++seen;
    return seen;
}

double SegmentIndex::candidate_fraction(const float* query, double radius) const {
    if (size_ == 0) return 0.0;
    return static_cast<double>(count_candidates(query, radius)) / static_cast<double>(size_);
}

void SegmentIndex::probe(const float* query, double radius) {
    if (stats_.queries > 0 || size_ == 0) return;
    candidate_fraction_ = static_cast<double>(count_candidates(query, radius)) / static_cast<double>(size_);
    brute_force_ = candidate_fraction_ > kBruteAbove;
}

void SegmentIndex::learn(std::size_t queries, std::size_t candidates_per_query) {
    stats_.queries += queries;
    stats_.candidates += queries * candidates_per_query;
    if (brute_force()) stats_.linear_queries += queries;
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
    // the tree path checks each query as it starts it (prepare() computes
    // the largest magnitude); the others check them all first
    if (brute_force() || levels_.empty()) require_finite(std::span<const float>(queries, count * dim()), dim());
    if (brute_force()) {
        brute_batch(values, queries, count, radius, out);
    } else if (levels_.empty()) {
        for (std::size_t i = 0; i < count; ++i) out[i] = search_within(values, queries + i * dim(), radius, false, nullptr);
    } else {
        tree_batch(values, queries, count, radius, out);
    }
}

void SegmentIndex::nearest_within_batch_adaptive(std::span<const float> values, const float* queries,
                                                 std::size_t count, double radius,
                                                 std::span<std::optional<Neighbour>> out) {
    STEPSTONE_ASSERT(out.size() >= count);
    if (count == 0) return;
    if (!brute_force()) {
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
    if (huge_) {
        Best all;
        for (std::size_t id = 0; id < size_; ++id)
            all.offer(id, squared_distance(query, values.data() + id * n_dim, n_dim));
        return all.n;
    }

    // an upper bound: the exact distance of the lower-bound nearest of each
    // tree, and of the first buffered segment
    Best best;
    const Search q = prepare(query);
    for (const auto& level : levels_) {
        const std::size_t id = level->tree.near_leaf_point(q.point_f.data());
        best.offer(id, squared_distance(query, values.data() + id * n_dim, n_dim));
    }
    const std::size_t indexed = levels_.empty() ? 0 : levels_.back()->end();
    if (indexed < size_) best.offer(indexed, squared_distance(query, values.data() + indexed * n_dim, n_dim));
    STEPSTONE_ASSERT(best.found);

    // every segment at most that far is within a radius whose square exceeds it
    const double radius = radius_covering(best.n.squared_distance);
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
