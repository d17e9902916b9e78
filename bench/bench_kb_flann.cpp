// `kb-flann`: the knowledge base's exact lookups against FLANN's randomized
// kd-forest (4 trees, 128 checks), the approximate index the knowledge-base
// issue names as the reference, on the realistic workload of the `kb` case.

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <optional>
#include <vector>

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wall"
#pragma GCC diagnostic ignored "-Wextra"
#pragma GCC diagnostic ignored "-Wconversion"
#pragma GCC diagnostic ignored "-Wsign-conversion"
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wold-style-cast"
#pragma GCC diagnostic ignored "-Wuseless-cast"
#include <flann/flann.hpp>
#pragma GCC diagnostic pop

#include "bench/bench_kb.hpp"
#include "kb/distance.hpp"

namespace stepstone::bench {

namespace {

using Clock = std::chrono::steady_clock;
using FlannIndex = flann::Index<flann::L2<float>>;

constexpr int kTrees = 4;
constexpr int kChecks = 128;
// FLANN draws its split dimensions from rand(); Debian's 1.9.2 shuffles the
// points with std::random_device, so the forest (and its recall) still varies
// slightly from run to run
constexpr unsigned kFlannSeed = 0x5eed;

// the KB's segments as a FLANN dataset (FLANN keeps pointers into them)
std::unique_ptr<FlannIndex> build_flann(const kb::KnowledgeBase& kb) {
    const std::size_t dim = kb.params().dim();
    const flann::Matrix<float> data(const_cast<float*>(kb.values().data()), kb.size(), dim);
    std::srand(kFlannSeed);
    auto index = std::make_unique<FlannIndex>(data, flann::KDTreeIndexParams(kTrees));
    index->buildIndex();
    return index;
}

struct FlannState {
    KbQueries data;
    std::unique_ptr<FlannIndex> flann;
    std::vector<std::size_t> ids;
    std::vector<float> squared;  // FLANN's L2 is the squared Euclidean distance

    std::size_t dim() const { return data.kb.params().dim(); }
    std::size_t queries() const { return data.queries.size() / dim(); }
    std::size_t policies() const { return queries() / kSegmentsPerPolicy; }
    const float* policy(std::size_t p) const { return data.queries.data() + p * kSegmentsPerPolicy * dim(); }

    // FLANN's nearest neighbour of every query, a policy (200 segments) per call
    void search_flann() {
        ids.resize(queries());
        squared.resize(queries());
        const flann::SearchParams params(kChecks);
        for (std::size_t p = 0; p < policies(); ++p) {
            const flann::Matrix<float> q(const_cast<float*>(policy(p)), kSegmentsPerPolicy, dim());
            flann::Matrix<std::size_t> indices(ids.data() + p * kSegmentsPerPolicy, kSegmentsPerPolicy, 1);
            flann::Matrix<float> distances(squared.data() + p * kSegmentsPerPolicy, kSegmentsPerPolicy, 1);
            flann->knnSearch(q, indices, distances, 1, params);
        }
    }

    // the exact within-delta match of every query, a policy per lookup (as r_max)
    double lookup_all() const {
        double sum = 0;
        for (std::size_t p = 0; p < policies(); ++p) {
            const kb::Segments segments{std::span<const float>(policy(p), kSegmentsPerPolicy * dim()), dim()};
            sum += data.kb.lookup(segments).r_max;
        }
        return sum;
    }
};

std::shared_ptr<FlannState> flann_state(Size size) {
    auto state = std::make_shared<FlannState>(FlannState{kb_queries(size), nullptr, {}, {}});
    state->flann = build_flann(state->data.kb);
    return state;
}

Workload make_flann_workload(Size size) {
    auto state = flann_state(size);
    Work baseline = [state] {
        state->search_flann();
        return static_cast<std::uint64_t>(state->queries());
    };
    Work candidate = [state] {
        const double sum = state->lookup_all();
        return static_cast<std::uint64_t>(state->queries()) + (std::isfinite(sum) ? 0 : 1);
    };
    return Workload{baseline, candidate};
}

}  // namespace

void add_kb_flann_case(Registry& registry) {
    registry.add(
        Case{"kb-flann", "segments",
             "lookups of one generation's segments (40,000 against a KB of 32,580): exact index vs FLANN "
             "kd-forest (4 trees, 128 checks, approximate)",
             10.0, make_flann_workload});
}

KbFlannMeasurements measure_kb_flann(Size size) {
    KbFlannMeasurements m;
    KbQueries data = kb_queries(size);
    const std::size_t dim = data.kb.params().dim();
    m.kb_size = data.kb.size();
    m.queries = data.queries.size() / dim;

    // the exact index, rebuilt from the KB's arrays as a loaded KB is
    auto t = Clock::now();
    {
        const std::vector<kb::Source> sources(data.kb.sources().begin(), data.kb.sources().end());
        data.kb =
            kb::KnowledgeBase::from_segments(data.kb.params(), sources, data.kb.values(), data.kb.records());
    }
    m.kb_build_seconds = seconds_since(t);

    FlannState state{std::move(data), nullptr, {}, {}};
    t = Clock::now();
    state.flann = build_flann(state.data.kb);
    m.flann_build_seconds = seconds_since(t);

    t = Clock::now();
    state.search_flann();
    m.flann_queries_per_s = static_cast<double>(m.queries) / seconds_since(t);
    t = Clock::now();
    (void)state.lookup_all();
    m.lookup_queries_per_s = static_cast<double>(m.queries) / seconds_since(t);

    const kb::KnowledgeBase& kb = state.data.kb;
    std::vector<std::optional<kb::Neighbour>> exact(m.queries);
    t = Clock::now();
    for (std::size_t i = 0; i < m.queries; ++i)
        exact[i] = kb.nearest(std::span<const float>(state.data.queries.data() + i * dim, dim));
    m.nearest_queries_per_s = static_cast<double>(m.queries) / seconds_since(t);

    // recall: FLANN's neighbour is the exact nearest (or ties with it)
    const double delta2 = kb.params().delta * kb.params().delta;
    std::size_t hits = 0, agree = 0, within = 0;
    for (std::size_t i = 0; i < m.queries; ++i) {
        const float* q = state.data.queries.data() + i * dim;
        const std::size_t id = state.ids[i];
        const double d2 = kb::squared_distance(q, kb.values().data() + id * dim, dim);
        const bool hit = id == exact[i]->id || d2 == exact[i]->squared_distance;
        hits += hit ? 1 : 0;
        const bool exact_within = exact[i]->squared_distance < delta2;
        within += exact_within ? 1 : 0;
        // the within-delta rule: the nearest if closer than delta, else none
        agree += (exact_within ? hit : !(d2 < delta2)) ? 1 : 0;
    }
    m.recall = static_cast<double>(hits) / static_cast<double>(m.queries);
    m.match_agreement = static_cast<double>(agree) / static_cast<double>(m.queries);
    m.within_delta = static_cast<double>(within) / static_cast<double>(m.queries);
    return m;
}

}  // namespace stepstone::bench
