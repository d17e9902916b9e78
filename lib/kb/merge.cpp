// KnowledgeBase::merge and KnowledgeBase::randomized: the two ways of making
// a KB out of others (kb merge, kb randomize).

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/error.hpp"
#include "core/rng.hpp"
#include "core/text.hpp"
#include "kb/knowledge_base.hpp"

namespace stepstone::kb {

namespace {

void check_compatible(const KbParams& a, const KbParams& b) {
    if (a.segment_width != b.segment_width) {
        throw DataError(concat("cannot merge: segment_width is ", a.segment_width, " in the target, ",
                               b.segment_width, " in the merged knowledge base"));
    }
    if (a.channels != b.channels) {
        throw DataError(concat("cannot merge: channels is ", a.channels, " in the target, ", b.channels,
                               " in the merged knowledge base"));
    }
    if (a.delta != b.delta) {
        throw DataError(concat("cannot merge: delta is ", shortest(a.delta), " in the target, ",
                               shortest(b.delta), " in the merged knowledge base"));
    }
    if (a.counting != b.counting) {
        throw DataError(concat("cannot merge: the target counts by ", to_string(a.counting),
                               ", the merged knowledge base by ", to_string(b.counting)));
    }
}

}  // namespace

void KnowledgeBase::merge(const KnowledgeBase& other) {
    check_compatible(params_, other.params_);
    if (&other == this) {
        const KnowledgeBase copy(other);
        absorb(copy);
        return;
    }
    absorb(other);
}

KnowledgeBase KnowledgeBase::coarsened(double delta) const {
    if (!std::isfinite(delta) || delta < params_.delta) {
        throw ConfigError(concat("a coarser delta must be finite and at least the KB's ", shortest(params_.delta),
                                 ", got ", shortest(delta)));
    }
    KbParams params = params_;
    params.delta = delta;
    KnowledgeBase out(params);
    out.absorb(*this);
    return out;
}

void KnowledgeBase::absorb(const KnowledgeBase& other) {

    // sources: same run name, same source; the others are appended
    std::vector<std::uint32_t> source_map(other.sources_.size());
    for (std::size_t i = 0; i < other.sources_.size(); ++i) {
        const Source& theirs = other.sources_[i];
        const std::uint32_t mine = add_source(theirs.run);
        Source& s = sources_[mine];
        if (s.policies == 0) {
            s.first_generation = theirs.first_generation;
            s.last_generation = theirs.last_generation;
        } else if (theirs.policies > 0) {
            s.first_generation = std::min(s.first_generation, theirs.first_generation);
            s.last_generation = std::max(s.last_generation, theirs.last_generation);
        }
        s.policies += theirs.policies;
        source_map[i] = mine;
    }
    auto remap = [&](Origin o) { return Origin{source_map[o.source], o.generation}; };

    // the other KB's segments observed one by one, carrying their statistics
    const std::size_t dim = params_.dim();
    for (std::size_t i = 0; i < other.size(); ++i) {
        const float* s = other.values_.data() + i * dim;
        const SegmentRecord& theirs = other.records_[i];
        const auto near = index_.nearest_within_adaptive(values_, s, params_.delta);
        if (near) {
            changed();
            SegmentRecord& r = records_[near->id];
            r.cum_reward += theirs.cum_reward;
            r.count += theirs.count;
            r.last = remap(theirs.last);
        } else {
            insert(s, SegmentRecord{theirs.cum_reward, theirs.count, remap(theirs.first), remap(theirs.last)});
        }
    }
}

KnowledgeBase KnowledgeBase::randomized(std::uint64_t seed) const {
    KnowledgeBase copy(*this);
    copy.changed();
    Rng rng(seed, 0, 0, Purpose::kb_randomize);
    for (SegmentRecord& r : copy.records_) {
        r.cum_reward = rng.uniform();
        r.count = 1;
    }
    return copy;
}

}  // namespace stepstone::kb
