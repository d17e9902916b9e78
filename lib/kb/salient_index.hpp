#pragma once

#include <cstddef>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "kb/detail/huge_pages.hpp"
#include "kb/segment_index.hpp"
#include "kb/signature_scan.hpp"

namespace stepstone::kb {

struct SegmentRecord;

/// The segments of a knowledge base whose average reward is positive, in
/// indexes of their own: the shortcut behind KnowledgeBase::r_max.
///
/// A source task rewards few of its policies, so most KB segments average 0
/// and the positive ones are a small minority. When
/// no average is negative, r_max is the largest average among the policy
/// segments' matches (0 if none), and a segment can raise the running r_max t
/// only if its match averages more than t. So the positive segments are cut,
/// by decreasing average, into bands of growing size (256, 1,024, 4,096, ...),
/// each indexed on its own, and a policy's segments are searched band by band
/// from the top. Each query keeps the nearest positive segment h found so far
/// (under the match rule); h stands for the query only if no KB segment lies
/// nearer, which a search of the full index bounded by h's distance settles
/// (its answer is then the query's exact match, h or a segment of a lower
/// band or averaging 0). After a band, queries whose h cannot beat t, and
/// queries settled by the full search, drop out; the search stops as soon as
/// t reaches the band's lowest average, since every segment that could still
/// raise t has then been searched.
///
/// When some channels of the KB hold only 0 and 1 (a source run's KB: 9 of
/// 15) and at most 4,096 segments are positive, every search is a SignatureScan: the bands' and the bounded
/// full search, over signatures of every KB segment. A query of the paper's task is ruled out by its Hamming
/// distance to most segments before any float is read, which beats the trees of a SegmentIndex on these data
/// (the index's block-means bound is weak on 0/1 values). Otherwise each band has a SegmentIndex and the full
/// search is the KB's own index.
///
/// Every answer equals KnowledgeBase::lookup(segments).r_max bit for bit: the
/// searches are exact, ties go to the lowest KB id (each band keeps the KB's
/// order, and bands are compared by distance, then id), and a bounded full
/// search returns the KB's own nearest segment.
class SalientIndex {
public:
    /// The positive segments of a KB of segments of `width` x `channels`
    /// values matched within `delta`, nullptr when the shortcut does not
    /// apply or would not pay: an average below 0 (or -0.0), or more than
    /// half the segments positive.
    static std::unique_ptr<SalientIndex> build(std::size_t width, std::size_t channels, double delta,
                                               std::span<const float> values,
                                               std::span<const SegmentRecord> records);

    /// Number of positive segments.
    std::size_t size() const;
    /// Number of bands.
    std::size_t bands() const { return bands_.size(); }
    /// True when searches are signature scans (the KB has binary channels).
    bool scans() const { return all_.has_value(); }

    /// lookup().r_max of the `count` segments at `queries` (dim() values
    /// each, finite) against the KB of `values` and `records`, indexed by
    /// `full`: within `delta` when set, else whatever the distance.
    double r_max(const float* queries, std::size_t count, std::optional<double> delta,
                 const SegmentIndex& full, std::span<const float> values,
                 std::span<const SegmentRecord> records) const;

    /// Bytes held per positive segment (values, KB id, index or signatures,
    /// and the signatures of every KB segment).
    double bytes_per_segment() const;

private:
    struct Band {
        std::vector<std::size_t> ids;      // KB id of each segment of the band, increasing
        detail::HugeVector<float> values;  // their values, back to back
        std::optional<SegmentIndex> index;  // without signatures
        std::optional<SignatureScan> scan;  // with signatures
        double lowest = 0.0;  // the band's lowest average
    };
    SalientIndex() = default;

    std::vector<std::unique_ptr<Band>> bands_;  // by decreasing average
    std::optional<SignatureScan> all_;          // every KB segment, when the KB has binary channels
};

}  // namespace stepstone::kb
