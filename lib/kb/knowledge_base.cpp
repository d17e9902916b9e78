#include "kb/knowledge_base.hpp"

#include <xxhash.h>

#include <algorithm>
#include <cmath>
#include <mutex>
#include <string_view>
#include <unordered_map>

#include "core/assert.hpp"
#include "core/error.hpp"
#include "core/text.hpp"
#include "kb/distance.hpp"
#include "kb/salient_index.hpp"

namespace stepstone::kb {

namespace detail {

// the index of positive segments, built by the first r_max() that needs it
struct SalientSlot {
    std::mutex mutex;
    bool built = false;
    std::unique_ptr<SalientIndex> index;
};

}  // namespace detail

const char* to_string(Counting counting) { return counting == Counting::policy ? "policy" : "occurrence"; }

Counting parse_counting(std::string_view text, std::string_view what) {
    if (text == "occurrence") return Counting::occurrence;
    if (text == "policy") return Counting::policy;
    throw ConfigError(concat(what, " must be one of occurrence|policy, got \"", text, '"'));
}

void KbParams::validate() const {
    if (!(delta > 0) || !std::isfinite(delta)) {
        throw ConfigError(concat("delta must be > 0 and finite, got ", shortest(delta)));
    }
    if (segment_width < 1) throw ConfigError(concat("segment_width must be >= 1, got ", segment_width));
    if (channels < 1) throw ConfigError(concat("channels must be >= 1, got ", channels));
}

namespace {

KbParams validated(KbParams params) {
    params.validate();
    return params;
}

}  // namespace

KnowledgeBase::KnowledgeBase(KbParams params)
    : params_(validated(params)),
      index_(params_.segment_width, params_.channels),
      salient_(std::make_unique<detail::SalientSlot>()) {}

KnowledgeBase::KnowledgeBase(const KnowledgeBase& other)
    : params_(other.params_),
      values_(other.values_),
      records_(other.records_),
      sources_(other.sources_),
      index_(other.index_),
      salient_(std::make_unique<detail::SalientSlot>()) {}

KnowledgeBase& KnowledgeBase::operator=(const KnowledgeBase& other) {
    if (this != &other) {
        KnowledgeBase copy(other);
        *this = std::move(copy);
    }
    return *this;
}

KnowledgeBase::KnowledgeBase(KnowledgeBase&&) noexcept = default;
KnowledgeBase& KnowledgeBase::operator=(KnowledgeBase&&) noexcept = default;
KnowledgeBase::~KnowledgeBase() = default;

KnowledgeBase KnowledgeBase::from_segments(KbParams params, std::vector<Source> sources,
                                           std::span<const float> values,
                                           std::span<const SegmentRecord> records) {
    KnowledgeBase kb(params);
    const std::size_t dim = kb.params_.dim();
    if (values.size() != records.size() * dim) {
        throw DataError(concat("knowledge base: ", values.size(), " values for ", records.size(),
                               " segments of ", dim, " values"));
    }
    if (const std::size_t k = first_non_finite(values); k < values.size()) {
        throw DataError(concat("knowledge base: segment ", k / dim, " has a non-finite value at position ",
                               k % dim));
    }
    for (std::size_t i = 0; i < sources.size(); ++i) {
        check_run_name(sources[i].run, concat("knowledge base: source ", i, "'s run name"));
        for (std::size_t j = 0; j < i; ++j) {
            if (sources[j].run == sources[i].run) {
                throw DataError(concat("knowledge base: source '", sources[i].run, "' is listed twice"));
            }
        }
    }
    for (std::size_t i = 0; i < records.size(); ++i) {
        const SegmentRecord& r = records[i];
        if (r.count == 0) throw DataError(concat("knowledge base: segment ", i, " has count 0"));
        if (!std::isfinite(r.cum_reward)) {
            throw DataError(concat("knowledge base: segment ", i, " has a non-finite cum_reward"));
        }
        if (!(std::abs(r.cum_reward) <= static_cast<double>(r.count) * kMaxRewardMagnitude)) {
            throw DataError(concat("knowledge base: segment ", i, " has cum_reward ", shortest(r.cum_reward),
                                   " over ", r.count, " policies, beyond their rewards' bound (+-",
                                   shortest(kMaxRewardMagnitude), " each)"));
        }
        if (r.first.source >= sources.size() || r.last.source >= sources.size()) {
            throw DataError(concat("knowledge base: segment ", i, " names source ",
                                   std::max(r.first.source, r.last.source), " of ", sources.size()));
        }
    }
    kb.values_.assign(values.begin(), values.end());
    kb.records_.assign(records.begin(), records.end());
    kb.sources_ = std::move(sources);
    kb.index_.assign(kb.values_);
    return kb;
}

std::span<const float> KnowledgeBase::segment(std::size_t id) const {
    STEPSTONE_ASSERT(id < size());
    return std::span<const float>(values_).subspan(id * params_.dim(), params_.dim());
}

double KnowledgeBase::max_average() const {
    double best = 0.0;
    bool any = false;
    for (const SegmentRecord& r : records_) {
        if (!any || r.average() > best) best = r.average();
        any = true;
    }
    return best;
}

void check_run_name(std::string_view name, std::string_view what) {
    if (name.empty()) throw DataError(concat(what, " is empty"));
    if (name.size() > kMaxRunName) {
        throw DataError(concat(what, " has ", name.size(), " bytes, more than ", kMaxRunName));
    }
    // UTF-8: a lead byte, then as many continuation bytes (10xxxxxx) as it announces;
    // no overlong forms, surrogates or code points beyond U+10FFFF
    for (std::size_t i = 0; i < name.size();) {
        const auto b = static_cast<unsigned char>(name[i]);
        if (b < 0x20 || b == 0x7f) throw DataError(concat(what, " holds a control character (byte ", i, ")"));
        std::size_t extra = 0;
        std::uint32_t code = b;
        if (b >= 0xf0 && b <= 0xf4) {
            extra = 3, code = b & 0x07u;
        } else if (b >= 0xe0 && b <= 0xef) {
            extra = 2, code = b & 0x0fu;
        } else if (b >= 0xc2 && b <= 0xdf) {
            extra = 1, code = b & 0x1fu;
        } else if (b >= 0x80) {
            throw DataError(concat(what, " is not valid UTF-8 (byte ", i, ")"));
        }
        for (std::size_t k = 1; k <= extra; ++k) {
            const auto c = i + k < name.size() ? static_cast<unsigned char>(name[i + k]) : 0u;
            if ((c & 0xc0u) != 0x80u) throw DataError(concat(what, " is not valid UTF-8 (byte ", i, ")"));
            code = (code << 6) | (c & 0x3fu);
        }
        const bool overlong = (extra == 2 && code < 0x800) || (extra == 3 && code < 0x10000);
        if (overlong || (code >= 0xd800 && code <= 0xdfff) || code > 0x10ffff) {
            throw DataError(concat(what, " is not valid UTF-8 (byte ", i, ")"));
        }
        i += extra + 1;
    }
}

std::uint32_t KnowledgeBase::add_source(const std::string& run) {
    check_run_name(run, "knowledge base: a source's run name");
    for (std::size_t i = 0; i < sources_.size(); ++i)
        if (sources_[i].run == run) return static_cast<std::uint32_t>(i);
    sources_.push_back(Source{run, 0, 0, 0});
    return static_cast<std::uint32_t>(sources_.size() - 1);
}

void KnowledgeBase::check_segments(Segments segments) const {
    if (segments.dim != params_.dim()) {
        throw DataError(concat("segments have ", segments.dim, " values, the knowledge base uses ",
                               params_.dim(), " (", params_.segment_width, " steps x ", params_.channels,
                               " channels)"));
    }
    if (segments.values.size() % segments.dim != 0) {
        throw DataError(concat("segments: ", segments.values.size(), " values is not a whole number of segments of ",
                               segments.dim, " values"));
    }
    require_finite(segments.values, segments.dim);
}

void KnowledgeBase::changed() {
    if (!salient_) salient_ = std::make_unique<detail::SalientSlot>();  // a moved-from KB assigned anew
    salient_->built = false;
    salient_->index.reset();
}

const SalientIndex* KnowledgeBase::salient() const {
    if (!salient_) return nullptr;
    const std::lock_guard lock(salient_->mutex);
    if (!salient_->built) {
        salient_->index =
            SalientIndex::build(params_.segment_width, params_.channels, params_.delta, values_, records_);
        salient_->built = true;
    }
    return salient_->index.get();
}

void KnowledgeBase::insert(const float* segment, const SegmentRecord& record) {
    changed();
    values_.insert(values_.end(), segment, segment + params_.dim());
    records_.push_back(record);
    index_.append(segment);
}

ObserveResult KnowledgeBase::observe(Segments segments, double reward, Origin origin) {
    // validate everything before touching the KB
    check_segments(segments);
    if (!std::isfinite(reward)) throw DataError(concat("reward must be finite, got ", shortest(reward)));
    if (std::abs(reward) > kMaxRewardMagnitude) {
        throw DataError(concat("reward ", shortest(reward), " is beyond +-", shortest(kMaxRewardMagnitude),
                               ", the largest a KB sums without overflow"));
    }
    if (origin.source >= sources_.size()) {
        throw DataError(concat("observation names source ", origin.source, ", the knowledge base has ",
                               sources_.size()));
    }

    // on the brute-force path, the whole policy is first searched against
    // the KB as it was before the call (one pass over the KB); the segments
    // this call inserts are checked one by one below. They have higher ids, so
    // they win only when strictly closer, which is what the sequential rule gives
    ObserveResult result;
    const std::size_t dim = params_.dim();
    const std::size_t before = size();
    if (segments.size() > 0) index_.probe(segments.values.data(), params_.delta);
    const bool snapshot_first = index_.brute_force() && segments.size() > 1;
    std::vector<std::optional<Neighbour>> snapshot;
    if (snapshot_first) {
        snapshot.resize(segments.size());
        index_.nearest_within_batch_adaptive(values_, segments.values.data(), segments.size(), params_.delta,
                                             snapshot);
    }

    // the paper's rule, one segment at a time; under Counting::policy the KB
    // segments this call has credited or inserted are not credited again
    const double delta_sq = params_.delta * params_.delta;
    const bool once = params_.counting == Counting::policy;
    std::vector<std::size_t> credited;
    for (std::size_t i = 0; i < segments.size(); ++i) {
        const float* s = segments.values.data() + i * dim;
        std::optional<Neighbour> near;
        if (snapshot_first) {
            near = snapshot[i];
            for (std::size_t id = before; id < size(); ++id) {
                const double bound = near ? near->squared_distance : delta_sq;
                const double d2 = squared_distance_up_to(s, values_.data() + id * dim, dim, bound);
                if (d2 < delta_sq && (!near || d2 < near->squared_distance)) near = Neighbour{id, d2};
            }
        } else {
            near = index_.nearest_within_adaptive(values_, s, params_.delta);
        }
        if (near) {
            ++result.matched;
            if (once) {
                if (near->id >= before ||
                    std::find(credited.begin(), credited.end(), near->id) != credited.end())
                    continue;
                credited.push_back(near->id);
            }
            changed();
            SegmentRecord& r = records_[near->id];
            r.cum_reward += reward;
            r.count += 1;
            r.last = origin;
        } else {
            insert(s, SegmentRecord{reward, 1, origin, origin});
            ++result.inserted;
        }
    }

    // provenance of the source
    Source& source = sources_[origin.source];
    if (source.policies == 0) {
        source.first_generation = origin.generation;
        source.last_generation = origin.generation;
    } else {
        source.first_generation = std::min(source.first_generation, origin.generation);
        source.last_generation = std::max(source.last_generation, origin.generation);
    }
    source.policies += 1;
    return result;
}

SegmentMatch KnowledgeBase::match_of(const float* segment) const {
    const auto near = params_.match == Match::nearest ? index_.nearest(values_, segment)
                                                      : index_.nearest_within(values_, segment, params_.delta);
    if (!near) return SegmentMatch{};
    return SegmentMatch{near->id, std::sqrt(near->squared_distance), records_[near->id].average()};
}

bool KnowledgeBase::batch_search(Segments segments) const {
    return params_.match == Match::within_delta && segments.size() > 1;
}

std::vector<float> KnowledgeBase::distinct_of(Segments segments, std::vector<std::size_t>& slot) const {
    // a robot standing still, pushing a wall or circling shows the same
    // segment again and again: each distinct one (bit for bit) is searched
    // once, which leaves every match as it was
    const std::size_t dim = params_.dim();
    slot.resize(segments.size());
    std::vector<float> distinct;
    distinct.reserve(segments.values.size());
    // (XXH3 of a segment's bytes: std::hash of a string_view took ~6 % of a lookup)
    struct BytesHash {
        std::size_t operator()(std::string_view bytes) const {
            return XXH3_64bits(bytes.data(), bytes.size());
        }
    };
    std::unordered_map<std::string_view, std::size_t, BytesHash> seen;
    seen.reserve(segments.size());
    for (std::size_t i = 0; i < segments.size(); ++i) {
        const auto* bytes = reinterpret_cast<const char*>(segments.values.data() + i * dim);
        const auto [it, fresh] = seen.try_emplace(std::string_view(bytes, dim * sizeof(float)), seen.size());
        if (fresh)
            distinct.insert(distinct.end(), segments.values.data() + i * dim,
                            segments.values.data() + (i + 1) * dim);
        slot[i] = it->second;
    }
    return distinct;
}

std::vector<SegmentMatch> KnowledgeBase::matches_of(Segments segments) const {
    const std::size_t dim = params_.dim();
    std::vector<std::size_t> slot;
    const std::vector<float> distinct = distinct_of(segments, slot);
    const std::size_t count = distinct.size() / dim;

    std::vector<SegmentMatch> found;
    found.reserve(count);
    if (batch_search(segments)) {
        // the whole policy at once: one pass over the KB (brute force) or
        // interleaved tree walks
        std::vector<std::optional<Neighbour>> near(count);
        index_.nearest_within_batch(values_, distinct.data(), count, params_.delta, near);
        for (const auto& n : near) {
            found.push_back(n ? SegmentMatch{n->id, std::sqrt(n->squared_distance), records_[n->id].average()}
                              : SegmentMatch{});
        }
    } else {
        for (std::size_t k = 0; k < count; ++k) found.push_back(match_of(distinct.data() + k * dim));
    }

    std::vector<SegmentMatch> out;
    out.reserve(segments.size());
    for (const std::size_t k : slot) out.push_back(found[k]);
    return out;
}

Lookup KnowledgeBase::lookup(Segments segments) const {
    // checked here rather than by the index's batch search, which sees only
    // the distinct segments and would name them by their place among those
    check_segments(segments);
    Lookup result;
    result.segments = matches_of(segments);
    // a segment without a match contributes 0, so r_max is the largest of
    // the per-segment average_reward values (0 for no segments)
    for (std::size_t i = 0; i < result.segments.size(); ++i) {
        const double reward = result.segments[i].average_reward;
        result.r_max = i == 0 ? reward : std::max(result.r_max, reward);
    }
    return result;
}

double KnowledgeBase::r_max(Segments segments) const {
    const SalientIndex* positive = segments.size() > 0 ? salient() : nullptr;
    if (positive == nullptr) return lookup(segments).r_max;
    check_segments(segments);
    std::vector<std::size_t> slot;
    const std::vector<float> distinct = distinct_of(segments, slot);
    const std::optional<double> delta =
        params_.match == Match::within_delta ? std::optional<double>(params_.delta) : std::nullopt;
    return positive->r_max(distinct.data(), distinct.size() / params_.dim(), delta, index_, values_,
                           records_);
}

std::optional<Neighbour> KnowledgeBase::nearest(std::span<const float> segment) const {
    if (segment.size() != params_.dim()) {
        throw DataError(concat("segment has ", segment.size(), " values, the knowledge base uses ", params_.dim()));
    }
    check_segments(Segments{segment, params_.dim()});
    return index_.nearest(values_, segment.data());
}

double KnowledgeBase::bytes_per_segment() const {
    return static_cast<double>(params_.dim() * sizeof(float) + sizeof(SegmentRecord)) + index_.bytes_per_segment();
}

}  // namespace stepstone::kb
