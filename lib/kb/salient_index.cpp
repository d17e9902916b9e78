#include "kb/salient_index.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "core/assert.hpp"
#include "kb/knowledge_base.hpp"

namespace stepstone::kb {

namespace {

// the top band's size; each next band is this many times larger
constexpr std::size_t kFirstBand = 256;
constexpr std::size_t kBandGrowth = 4;
// bands are used when a search of all positive segments would check more than
// this share of them in full (measured on a few of them as queries): 1.6 %
// at delta 1.83 and 5.1 % at 3.84 on a paper-size source run's KB, where one
// band was faster at 1.83 and bands 2.4x faster at 3.84
constexpr double kBandsAbove = 0.03;
// signature scans grow with the positive segments, the trees' searches far
// less: measured on shaped target runs, scans were 4x faster with 2,114
// positive segments (delta 1.83) and 1.3x with 3,700 (3.84), 1.3x slower
// with 4,600 and 2x slower with 19,022 (a paper-size KB at 1.83)
constexpr std::size_t kScanAtMost = 4096;

// a query's nearest positive segment so far (a KB id)
struct Nearest {
    bool found = false;
    std::size_t id = 0;
    double squared_distance = 0.0;

    // distance first, then the lowest id, as every search of the KB ranks them
    void offer(std::size_t kb_id, double d2) {
        if (!found || d2 < squared_distance || (d2 == squared_distance && kb_id < id)) {
            found = true;
            id = kb_id;
            squared_distance = d2;
        }
    }
};

}  // namespace

std::size_t SalientIndex::size() const {
    std::size_t n = 0;
    for (const auto& band : bands_) n += band->ids.size();
    return n;
}

std::unique_ptr<SalientIndex> SalientIndex::build(std::size_t width, std::size_t channels, double delta,
                                                  std::span<const float> values,
                                                  std::span<const SegmentRecord> records) {
    std::vector<std::size_t> positive;
    for (std::size_t id = 0; id < records.size(); ++id) {
        const double average = records[id].average();
        // a negative average (or -0.0) would make r_max negative or signed:
        // the full lookup alone defines it then
        if (std::signbit(average)) return nullptr;
        if (average > 0) positive.push_back(id);
    }
    if (positive.size() * 2 > records.size()) return nullptr;
    // by decreasing average, ties by id (any order would do: bands compare ids)
    std::stable_sort(positive.begin(), positive.end(), [&](std::size_t a, std::size_t b) {
        return records[a].average() > records[b].average();
    });

    const std::size_t dim = width * channels;
    std::unique_ptr<SalientIndex> salient(new SalientIndex());
    const std::vector<std::size_t> binary = positive.size() <= kScanAtMost
                                                ? SignatureScan::binary_channels(values, width, channels)
                                                : std::vector<std::size_t>{};
    if (!binary.empty()) {
        salient->all_.emplace(width, channels, binary);
        for (std::size_t id = 0; id < records.size(); ++id) salient->all_->add(values.data() + id * dim);
    }
    const auto make_band = [&](std::size_t begin, std::size_t end) {
        auto band = std::make_unique<Band>();
        band->lowest = records[positive[end - 1]].average();
        band->ids.assign(positive.begin() + static_cast<std::ptrdiff_t>(begin),
                         positive.begin() + static_cast<std::ptrdiff_t>(end));
        std::sort(band->ids.begin(), band->ids.end());  // the KB's order within the band
        band->values.reserve(band->ids.size() * dim);
        for (const std::size_t id : band->ids) {
            const float* segment = values.data() + id * dim;
            band->values.insert(band->values.end(), segment, segment + dim);
        }
        if (salient->all_) {
            band->scan.emplace(width, channels, binary);
            for (std::size_t k = 0; k < band->ids.size(); ++k) band->scan->add(band->values.data() + k * dim);
        } else {
            band->index.emplace(width, channels);
            band->index->assign(band->values);
            // tree or brute force, from how many of the band lie near one of them
            band->index->probe(band->values.data(), delta);
        }
        return band;
    };
    if (positive.empty()) return salient;
    // a scan's cost grows with its band: bands always. With trees, while the
    // bounds prune (a search checks few segments in full), a search costs
    // little more for more segments: one band; when each search checks a share
    // of them (large delta), its cost grows with the band: bands, so that a
    // policy searches only those that could raise its r_max
    if (!salient->all_) {
        auto all = make_band(0, positive.size());
        double fraction = 0.0;
        const std::size_t samples = std::min<std::size_t>(16, positive.size());
        for (std::size_t k = 0; k < samples; ++k)
            fraction += all->index->candidate_fraction(
                all->values.data() + (k * positive.size() / samples) * dim, delta);
        fraction /= static_cast<double>(samples);
        if (fraction <= kBandsAbove || positive.size() <= kFirstBand) {
            salient->bands_.push_back(std::move(all));
            return salient;
        }
    }
    std::size_t begin = 0;
    for (std::size_t size = kFirstBand; begin < positive.size(); size *= kBandGrowth) {
        const std::size_t end = std::min(positive.size(), begin + size);
        salient->bands_.push_back(make_band(begin, end));
        begin = end;
    }
    return salient;
}

double SalientIndex::r_max(const float* queries, std::size_t count, std::optional<double> delta,
                           const SegmentIndex& full, std::span<const float> values,
                           std::span<const SegmentRecord> records) const {
    const std::size_t dim = full.dim();
    // with signatures: each query's signature, computed once for every band
    // and confirming search
    std::optional<SignatureScan::Queries> prepared;
    if (all_) prepared = all_->prepare(queries, count);
    const double radius_sq = delta ? *delta * *delta : std::numeric_limits<double>::infinity();
    std::vector<Nearest> nearest(count);
    std::vector<std::size_t> open(count);  // queries whose match is not known yet
    std::iota(open.begin(), open.end(), std::size_t{0});
    std::vector<std::size_t> candidates;
    std::vector<float> gathered;
    std::vector<std::optional<Neighbour>> found;
    std::vector<bool> settled(count, false);
    const auto average = [&](std::size_t query) { return records[nearest[query].id].average(); };
    // the full KB's nearest segment within `radius`: its index where its trees
    // prune (a large KB), a scan where it would scan anyway
    const auto full_nearest = [&](std::size_t i, double radius) {
        if (all_ && (full.brute_force() || full.size() == 0))
            return all_->nearest((*prepared)[i], values.data(), radius * radius,
                                 std::numeric_limits<double>::infinity());
        const float* query = queries + i * dim;
        return std::isfinite(radius) ? full.nearest_within(values, query, radius)
                                     : full.nearest(values, query);
    };

    double r_max = 0.0;  // a segment without a match counts 0, and no average is below it
    for (const auto& band : bands_) {
        // each open query's nearest positive segment, this band included
        if (band->scan) {
            for (const std::size_t i : open) {
                // a segment that cannot equal the nearest so far is skipped
                const double worst =
                    nearest[i].found ? nearest[i].squared_distance : std::numeric_limits<double>::infinity();
                const auto near = band->scan->nearest((*prepared)[i], band->values.data(), radius_sq, worst);
                if (near) nearest[i].offer(band->ids[near->id], near->squared_distance);
            }
        } else if (delta) {
            // all at once: the index interleaves their walks
            gathered.clear();
            for (const std::size_t i : open)
                gathered.insert(gathered.end(), queries + i * dim, queries + (i + 1) * dim);
            found.assign(open.size(), std::nullopt);
            band->index->nearest_within_batch(band->values, gathered.data(), open.size(), *delta, found);
            for (std::size_t k = 0; k < open.size(); ++k)
                if (found[k]) nearest[open[k]].offer(band->ids[found[k]->id], found[k]->squared_distance);
        } else {
            for (const std::size_t i : open) {
                const auto near = band->index->nearest(band->values, queries + i * dim);
                if (near) nearest[i].offer(band->ids[near->id], near->squared_distance);
            }
        }

        // the queries whose nearest positive segment could raise r_max, best
        // first: the full KB's nearest settles each, and once one gives its
        // average, no later one can raise r_max
        candidates.clear();
        for (const std::size_t i : open)
            if (nearest[i].found && average(i) > r_max) candidates.push_back(i);
        std::stable_sort(candidates.begin(), candidates.end(),
                         [&](std::size_t a, std::size_t b) { return average(a) > average(b); });
        for (const std::size_t i : candidates) {
            if (!(average(i) > r_max)) break;
            const auto match = full_nearest(i, radius_covering(nearest[i].squared_distance));
            STEPSTONE_ASSERT(match.has_value());
            r_max = std::max(r_max, records[match->id].average());
            settled[i] = true;
        }
        // every segment averaging more than r_max has been searched
        if (r_max >= band->lowest) break;
        std::erase_if(open, [&](std::size_t i) { return settled[i]; });
        if (open.empty()) break;
    }
    return r_max;
}

double SalientIndex::bytes_per_segment() const {
    double bytes = 0.0;
    std::size_t n = 0;
    for (const auto& band : bands_) {
        const std::size_t dim = band->index ? band->index->dim() : band->scan->dim();
        const double per = static_cast<double>(dim * sizeof(float) + sizeof(std::size_t)) +
                           (band->index ? band->index->bytes_per_segment() : band->scan->bytes_per_segment());
        bytes += per * static_cast<double>(band->ids.size());
        n += band->ids.size();
    }
    if (all_) bytes += all_->bytes_per_segment() * static_cast<double>(all_->size());
    return n == 0 ? 0.0 : bytes / static_cast<double>(n);
}

}  // namespace stepstone::kb
