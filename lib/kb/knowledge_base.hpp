#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "kb/detail/huge_pages.hpp"
#include "kb/segment_index.hpp"
#include "kb/segments.hpp"

namespace stepstone::kb {

class SalientIndex;
namespace detail {
struct SalientSlot;
}

/// Which KB segment a lookup credits to a policy segment.
enum class Match {
    within_delta,  ///< the nearest KB segment if it lies closer than delta, else none
    nearest,       ///< the nearest KB segment whatever its distance
};

/// What observe() credits when one policy's segments match a KB segment.
enum class Counting {
    occurrence,  ///< every matching segment of the policy: reward and count once per match
    policy,  ///< the policy once (the paper's footnote 1): reward and a count of 1, however often it matched
};

/// "occurrence" or "policy".
const char* to_string(Counting counting);
/// The Counting named `text`; throws ConfigError naming `what` and the choices otherwise.
Counting parse_counting(std::string_view text, std::string_view what = "counting");

/// The paper's segment width: 20 time steps per segment.
inline constexpr std::size_t kDefaultSegmentWidth = 20;

/// Shape and rule of a knowledge base (the paper: width 20, 15 channels, delta 1.83).
struct KbParams {
    std::size_t segment_width = kDefaultSegmentWidth;  ///< time steps per segment (rows of the behaviour)
    std::size_t channels = 15;       ///< values per time step (sensors + effectors)
    double delta = 1.83;             ///< Euclidean threshold: "closer than delta" is dist < delta
    Match match = Match::within_delta;  ///< lookup rule (observe always uses delta)
    Counting counting = Counting::occurrence;  ///< observe's credit rule (lookups do not depend on it)

    /// Values per segment: segment_width * channels.
    std::size_t dim() const { return segment_width * channels; }
    /// Throws ConfigError (one line naming the value) unless delta is finite
    /// and > 0, segment_width >= 1 and channels >= 1.
    void validate() const;
};

/// The largest reward magnitude observe() accepts. A segment's cum_reward is a
/// sum of at most `count` rewards and a count stays below 2^63 (about
/// 9.2e18, the database's integer range), so |cum_reward| < 9.2e18 x 1e289 <
/// DBL_MAX: no sum can overflow, in observe() or merge(). A KB whose records
/// break |cum_reward| <= count x kMaxRewardMagnitude is refused on load.
inline constexpr double kMaxRewardMagnitude = 1e289;

/// The longest run name a KB source takes, in bytes.
inline constexpr std::size_t kMaxRunName = 256;

/// Throws DataError naming `what` unless `name` is a usable run name: 1 to
/// kMaxRunName bytes of valid UTF-8 without control characters (NUL included).
void check_run_name(std::string_view name, std::string_view what);

/// Where an observation comes from: a source (a run, registered with
/// KnowledgeBase::add_source) and a generation of it.
struct Origin {
    std::uint32_t source = 0;     ///< index into KnowledgeBase::sources()
    std::int64_t generation = 0;  ///< generation of the observed policies
};

/// The statistics and provenance of one KB segment.
struct SegmentRecord {
    double cum_reward = 0.0;  ///< sum of the rewards of the policies that exhibited it
    std::uint64_t count = 0;  ///< number of policies (observations) credited to it (>= 1)
    Origin first;             ///< the observation that inserted it
    Origin last;              ///< the latest observation credited to it

    /// cum_reward / count: the segment's saliency.
    double average() const { return cum_reward / static_cast<double>(count); }
};

/// A run (or other producer) that fed the knowledge base.
struct Source {
    std::string run;                  ///< the run's name (unique within one KB)
    std::int64_t first_generation = 0;  ///< first generation observed from it
    std::int64_t last_generation = 0;   ///< last generation observed from it
    std::uint64_t policies = 0;       ///< policies observed from it (merges add B's count)
};

/// What observe() did with a policy's segments.
struct ObserveResult {
    std::size_t matched = 0;   ///< segments credited to an existing KB segment
    std::size_t inserted = 0;  ///< segments added to the KB
};

/// The KB segment credited to one policy segment by a lookup.
struct SegmentMatch {
    std::optional<std::size_t> id;  ///< KB segment id, nullopt if none (empty KB, or none within delta)
    double distance = 0.0;          ///< Euclidean distance to it (0 when id is nullopt)
    double average_reward = 0.0;    ///< its average reward (0 when id is nullopt)
};

/// Every segment's match and the policy's r_max.
struct Lookup {
    std::vector<SegmentMatch> segments;  ///< one per policy segment, in order
    /// The largest average_reward among the segments, where a segment without
    /// a match counts 0; 0 for an empty KB or no segments.
    double r_max = 0.0;
};

/// The paper's knowledge base (Doncieux, "Transfer learning for direct policy
/// search: a reward shaping approach", section II): behaviour segments with
/// the cumulated reward and number of the policies that exhibited them.
///
/// Segments are stored as float32, back to back (segment id i at values()
/// [i * dim, (i + 1) * dim)); ids are insertion order and never change.
/// Results never depend on thread count: observe() is sequential by design,
/// and every nearest-neighbour answer is exact (see SegmentIndex).
class KnowledgeBase {
public:
    /// An empty KB. Throws ConfigError if params are invalid (KbParams::validate).
    explicit KnowledgeBase(KbParams params);
    /// Rebuilds the index from a loaded KB: `values` holds records.size()
    /// segments of params.dim() floats, each record a segment's statistics.
    /// Throws ConfigError for invalid params; DataError if sizes disagree, a
    /// value or reward is not finite, a count is 0, a cum_reward exceeds
    /// count x kMaxRewardMagnitude, a source's run name fails check_run_name,
    /// or a record names a source outside `sources`.
    static KnowledgeBase from_segments(KbParams params, std::vector<Source> sources,
                                       std::span<const float> values, std::span<const SegmentRecord> records);

    KnowledgeBase(const KnowledgeBase& other);
    KnowledgeBase& operator=(const KnowledgeBase& other);
    KnowledgeBase(KnowledgeBase&&) noexcept;
    KnowledgeBase& operator=(KnowledgeBase&&) noexcept;
    ~KnowledgeBase();

    /// The KB's shape and rule.
    const KbParams& params() const { return params_; }
    /// Number of segments.
    std::size_t size() const { return records_.size(); }
    /// Values of all segments, back to back.
    std::span<const float> values() const { return values_; }
    /// Values of segment `id` (id < size()).
    std::span<const float> segment(std::size_t id) const;
    /// Statistics and provenance of segment `id` (id < size()).
    const SegmentRecord& record(std::size_t id) const { return records_[id]; }
    /// Every segment's record, by id.
    std::span<const SegmentRecord> records() const { return records_; }
    /// The runs that fed this KB, by source index.
    std::span<const Source> sources() const { return sources_; }
    /// Largest average reward over the KB's segments (0 if empty); the `sum`
    /// treatment's normaliser.
    double max_average() const;

    /// Registers a source and returns its index; a name already present
    /// returns the existing index. Throws DataError if `run` is empty.
    std::uint32_t add_source(const std::string& run);

    /// Observes the segments of one policy that obtained `reward` (the paper's
    /// rule, section II.B). Segments are taken one at a time in order: for each,
    /// the nearest KB segment (ties: lowest id) is credited (cum_reward +=
    /// reward, count += 1, last = origin) if its distance is < delta, otherwise
    /// the segment is inserted with (reward, 1); a segment inserted earlier in
    /// the same call (or an earlier call) can therefore absorb later ones.
    /// Under Counting::policy a KB segment is credited at most once per call:
    /// a later match of the same KB segment (one this call inserted included)
    /// changes nothing but ObserveResult::matched. A
    /// generation is observed by calling this for each individual in index
    /// order. Throws DataError if a value or the reward is not finite, the
    /// segment dimension differs from params().dim(), or origin.source is not
    /// a registered source; the KB is then unchanged.
    ObserveResult observe(Segments segments, double reward, Origin origin);

    /// For each segment, its match under params().match and the policy's r_max.
    /// Throws DataError for a wrong dimension or a non-finite value.
    Lookup lookup(Segments segments) const;
    /// lookup(segments).r_max without the per-segment list, bit for bit.
    /// When no average is negative and at most half the segments have a
    /// positive one (a source run's KB), the first call builds an index of
    /// the positive segments (SalientIndex), kept until the KB changes, and
    /// the policy is searched there first; concurrent calls share it.
    double r_max(Segments segments) const;
    /// The nearest segment to `segment` whatever its distance (ties: lowest id),
    /// nullopt if the KB is empty. Throws DataError as lookup().
    std::optional<Neighbour> nearest(std::span<const float> segment) const;

    /// Observes every segment of `other` into this KB, in id order, under this
    /// KB's delta: a segment whose nearest is closer than delta adds its
    /// cum_reward and count to it (last = the other segment's last); others are
    /// inserted with their own record. Sources of `other` are appended (same
    /// name: same source, generations widened, policies added). Throws DataError
    /// naming both values if segment_width, channels, delta or the counting
    /// rule differ; the KB is then unchanged.
    void merge(const KnowledgeBase& other);

    /// The KB re-observed under a larger threshold: a new KB with delta
    /// `delta` into which this KB's segments are observed in id order,
    /// carrying their statistics, as merge() does (its sources are copied).
    /// Every segment this KB credited was within the old delta of a kept one,
    /// so it would have been credited under the new delta too; the result is
    /// what this KB's segments give, not what re-observing the policies would
    /// (a policy segment now falls to the nearest kept representative). Under
    /// Counting::policy, two segments that one policy credited and that now
    /// fall together add both counts: the count is then an upper bound.
    /// Throws ConfigError if `delta` is not finite or below this KB's delta.
    KnowledgeBase coarsened(double delta) const;

    /// A copy with the same segments, sources and provenance whose averages are
    /// drawn from U[0, 1): segment i (in id order) gets the i-th draw u of
    /// Rng(seed, 0, 0, Purpose::kb_randomize), and its record becomes
    /// cum_reward = u, count = 1, so average() == u exactly.
    KnowledgeBase randomized(std::uint64_t seed) const;

    /// Approximate memory per segment in bytes: values, record and index.
    double bytes_per_segment() const;
    /// The index (for its statistics).
    const SegmentIndex& index() const { return index_; }

private:
    // throws DataError on a wrong width or a non-finite value
    void check_segments(Segments segments) const;
    void insert(const float* segment, const SegmentRecord& record);
    SegmentMatch match_of(const float* segment) const;
    // true when matches_of() sends the policy to the index's batch search
    // (within delta, more than one segment)
    bool batch_search(Segments segments) const;
    std::vector<SegmentMatch> matches_of(Segments segments) const;
    // merge() without the parameter check
    void absorb(const KnowledgeBase& other);
    // the distinct segments (bit for bit) of `segments`, back to back, and
    // each segment's place among them
    std::vector<float> distinct_of(Segments segments, std::vector<std::size_t>& slot) const;
    // the index of positive segments, built on first use (nullptr: none applies)
    const SalientIndex* salient() const;
    // forgets that index (every change of values or records calls it)
    void changed();

    KbParams params_;
    detail::HugeVector<float> values_;
    std::vector<SegmentRecord> records_;
    std::vector<Source> sources_;
    SegmentIndex index_;
    std::unique_ptr<detail::SalientSlot> salient_;
};

}  // namespace stepstone::kb
