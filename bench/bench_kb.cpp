// `kb` cases: the knowledge base's exact index (lib/kb) against brute force
// (reference/brute_kb.hpp: batched distance matrices, the way the paper's
// workload would be done without the index).

#include "bench/bench_kb.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <numbers>
#include <utility>

#include "core/rng.hpp"
#include "kb/knowledge_base.hpp"
#include "reference/brute_kb.hpp"

namespace stepstone::bench {

namespace {

// the paper's shapes (docs/runs.md)
constexpr std::size_t kChannels = 15;
constexpr std::size_t kWidth = 20;
constexpr std::size_t kDim = kChannels * kWidth;
constexpr std::size_t kSteps = 4000;
static_assert(kSteps / kWidth == kSegmentsPerPolicy);
constexpr double kDelta = 1.83;
constexpr std::size_t kPaperKbSize = 32580;
constexpr std::size_t kPaperPopulation = 200;

// driving style shared by a family of policies
struct Style {
    double left, right, wobble, period, phase, action;
};

double clamp01(double v) { return v < 0 ? 0 : (v > 1 ? 1 : v); }

// distance from (x, y) along `angle` to the walls of the 600 x 400 box
double wall_distance(double x, double y, double angle) {
    const double dx = std::cos(angle), dy = std::sin(angle);
    double t = 1e9;
    if (dx > 1e-12) t = std::min(t, (600 - x) / dx);
    if (dx < -1e-12) t = std::min(t, -x / dx);
    if (dy > 1e-12) t = std::min(t, (400 - y) / dy);
    if (dy < -1e-12) t = std::min(t, -y / dy);
    return t;
}

Style random_style(Rng& rng) {
    Style s;
    s.left = rng.uniform();
    s.right = rng.uniform();
    s.wobble = rng.uniform(0, 0.3);
    s.period = rng.uniform(50, 400);
    s.phase = rng.uniform(0, 2 * std::numbers::pi);
    s.action = rng.bernoulli(0.5) ? 0.05 : 0.95;
    return s;
}

// a lineage member: the ancestor's style, slightly mutated
Style offspring(const Style& parent, Rng& rng) {
    Style s = parent;
    s.left = clamp01(s.left + rng.uniform(-0.01, 0.01));
    s.right = clamp01(s.right + rng.uniform(-0.01, 0.01));
    return s;
}

// one episode from the first start pose; `noise` stands for the controller's
// reaction to its inputs, shared by a lineage (deterministic controllers
// from one start repeat each other's behaviour until they diverge)
void drive(const Style& style, Rng& noise, std::size_t steps, float* out) {
    double x = 300, y = 200, heading = 0;
    double noise_l = 0, noise_r = 0;
    double action = style.action;
    bool lights[6] = {};
    bool carrying = false;
    for (std::size_t t = 0; t < steps; ++t) {
        // smooth wheel commands: style + slow oscillation + correlated noise
        noise_l = 0.95 * noise_l + noise.uniform(-0.02, 0.02);
        noise_r = 0.95 * noise_r + noise.uniform(-0.02, 0.02);
        const double wave =
            style.wobble *
            std::sin(2 * std::numbers::pi * static_cast<double>(t) / style.period + style.phase);
        const double left = clamp01(style.left + wave + noise_l);
        const double right = clamp01(style.right - wave + noise_r);
        if (noise.bernoulli(0.002)) action = 1 - action;
        if (noise.bernoulli(0.001)) carrying = !carrying;

        // differential drive, 4 units per step per wheel, blocked by the walls
        const double vl = 4 * (2 * left - 1), vr = 4 * (2 * right - 1);
        heading += (vr - vl) / 40;
        const double nx = x + 0.5 * (vl + vr) * std::cos(heading);
        const double ny = y + 0.5 * (vl + vr) * std::sin(heading);
        const bool blocked = nx < 20 || nx > 580 || ny < 20 || ny > 380;
        if (!blocked) {
            x = nx;
            y = ny;
        }
        // light sensors: pairs at +-pi/4 seeing one of three objects (ball
        // area, basket, switch) within a cone of +-pi/8 and 400 units
        static constexpr double kObjects[3][2] = {{97.5, 50.6}, {550, 350}, {300, 20}};
        for (int k = 0; k < 6; ++k) {
            const double* o = kObjects[k / 2];
            const double side = k % 2 == 0 ? std::numbers::pi / 4 : -std::numbers::pi / 4;
            const double off =
                std::remainder(std::atan2(o[1] - y, o[0] - x) - (heading + side), 2 * std::numbers::pi);
            lights[k] = std::fabs(off) < std::numbers::pi / 8 && std::hypot(o[0] - x, o[1] - y) < 400;
        }

        float* row = out + t * kChannels;
        row[0] = static_cast<float>(std::min(1.0, wall_distance(x, y, heading + std::numbers::pi / 4) / 320));
        row[1] = static_cast<float>(std::min(1.0, wall_distance(x, y, heading - std::numbers::pi / 4) / 320));
        row[2] = static_cast<float>(std::min(1.0, wall_distance(x, y, heading) / 320));
        for (int k = 0; k < 6; ++k) row[3 + k] = lights[k] ? 1.0f : 0.0f;
        row[9] = blocked && vl > 0 ? 1.0f : 0.0f;
        row[10] = blocked && vr > 0 ? 1.0f : 0.0f;
        row[11] = carrying ? 1.0f : 0.0f;
        row[12] = static_cast<float>(left);
        row[13] = static_cast<float>(right);
        row[14] = static_cast<float>(action);
    }
}

// ancestors shared by every synthetic generation, as one run's lineages
constexpr std::size_t kLineages = 40;
constexpr std::uint64_t kLineageSeed = 0x5eed;

}  // namespace

std::vector<float> synthetic_behaviours(std::uint64_t seed, std::size_t policies, std::size_t steps) {
    Rng ancestors(kLineageSeed);
    std::vector<Style> lineages;
    for (std::size_t f = 0; f < kLineages; ++f) lineages.push_back(random_style(ancestors));
    Rng rng(seed);
    std::vector<float> out(policies * steps * kChannels);
    for (std::size_t p = 0; p < policies; ++p) {
        const std::size_t lineage = static_cast<std::size_t>(rng.below(kLineages));
        const Style s = offspring(lineages[lineage], rng);
        Rng noise(kLineageSeed, 0, lineage, Purpose::controller);
        drive(s, noise, steps, out.data() + p * steps * kChannels);
    }
    return out;
}

double seconds_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

namespace {

using Clock = std::chrono::steady_clock;

kb::KbParams paper_params() {
    kb::KbParams p;
    p.segment_width = kWidth;
    p.channels = kChannels;
    p.delta = kDelta;
    return p;
}

// a KB grown from earlier synthetic generations, cut to `size` segments
kb::KnowledgeBase realistic_kb(std::size_t size, std::uint64_t seed) {
    kb::KnowledgeBase kb(paper_params());
    const std::uint32_t src = kb.add_source("synthetic");
    Rng rewards(seed, 0, 0, Purpose::test);
    for (std::uint64_t g = 1; kb.size() < size; ++g) {
        const std::vector<float> behaviours = synthetic_behaviours(seed + g, kPaperPopulation, kSteps);
        for (std::size_t p = 0; p < kPaperPopulation && kb.size() < size; ++p) {
            const std::span<const float> b(behaviours.data() + p * kSteps * kChannels, kSteps * kChannels);
            kb.observe(kb::segment_behaviour(b, kChannels, kWidth),
                       static_cast<double>(rewards.below(9)) / 24.0,
                       kb::Origin{src, static_cast<std::int64_t>(g)});
        }
    }
    std::vector<kb::Source> sources(kb.sources().begin(), kb.sources().end());
    return kb::KnowledgeBase::from_segments(paper_params(), sources, kb.values().first(size * kDim),
                                            kb.records().first(size));
}

kb::KnowledgeBase uniform_kb(std::size_t size, std::uint64_t seed) {
    Rng rng(seed);
    std::vector<float> values(size * kDim);
    for (float& v : values) v = static_cast<float>(rng.uniform());
    std::vector<kb::SegmentRecord> records(size, kb::SegmentRecord{0.5, 1, {0, 0}, {0, 0}});
    return kb::KnowledgeBase::from_segments(paper_params(), {kb::Source{"uniform", 0, 0, 1}}, values,
                                            records);
}

// one generation to observe: policies x 200 segments and their rewards
struct Generation {
    std::vector<float> values;
    std::vector<double> rewards;
    std::size_t policies = 0;

    const float* policy(std::size_t p) const { return values.data() + p * kSegmentsPerPolicy * kDim; }
    std::size_t queries() const { return policies * kSegmentsPerPolicy; }
};

Generation realistic_generation(std::size_t policies, std::uint64_t seed) {
    Generation g;
    g.values = synthetic_behaviours(seed, policies, kSteps);
    g.policies = policies;
    Rng rng(seed, 0, 1, Purpose::test);
    for (std::size_t p = 0; p < policies; ++p) g.rewards.push_back(static_cast<double>(rng.below(9)) / 24.0);
    return g;
}

Generation uniform_generation(std::size_t policies, std::uint64_t seed) {
    Generation g;
    Rng rng(seed);
    g.values.resize(policies * kSegmentsPerPolicy * kDim);
    for (float& v : g.values) v = static_cast<float>(rng.uniform());
    g.policies = policies;
    g.rewards.assign(policies, 0.5);
    return g;
}

// the candidate: a fresh copy of the KB observes the policies in order
std::size_t observe_with_index(kb::KnowledgeBase& kb, const Generation& g, std::size_t policies) {
    const std::uint32_t src = kb.add_source("generation");
    std::size_t inserted = 0;
    for (std::size_t p = 0; p < policies; ++p) {
        inserted +=
            kb.observe(kb::Segments{std::span<const float>(g.policy(p), kSegmentsPerPolicy * kDim), kDim},
                       g.rewards[p], kb::Origin{src, 0})
                .inserted;
    }
    return inserted;
}

struct Sizes {
    std::size_t kb_size, generation, batched_slice, uniform_kb, uniform_policies, load;
};

Sizes sizes_of(Size size) {
    if (size == Size::full) return {kPaperKbSize, kPaperPopulation, 4, kPaperKbSize, 2, 1000000};
    return {4000, 20, 2, 4000, 1, 50000};
}

struct KbState {
    KbState(kb::KnowledgeBase k, Generation g) : kb(std::move(k)), generation(std::move(g)), brute(kb) {}
    kb::KnowledgeBase kb;
    Generation generation;
    reference::BruteKb brute;
};

// both sides observe the generation into the KB as it was: the baseline its first
// `baseline_policies` policies by brute force (a slice: the whole generation would take
// minutes), the candidate all of them with the index
Workload observe_workload(kb::KnowledgeBase base, Generation generation, std::size_t baseline_policies) {
    auto state = std::make_shared<KbState>(std::move(base), std::move(generation));
    Work baseline = [state, baseline_policies] {
        state->brute.reset();
        for (std::size_t p = 0; p < baseline_policies; ++p)
            state->brute.observe_batched(state->generation.policy(p), kSegmentsPerPolicy,
                                         state->generation.rewards[p]);
        return static_cast<std::uint64_t>(baseline_policies * kSegmentsPerPolicy);
    };
    Work candidate = [state] {
        kb::KnowledgeBase kb = state->kb;
        observe_with_index(kb, state->generation, state->generation.policies);
        return static_cast<std::uint64_t>(state->generation.queries());
    };
    return Workload{baseline, candidate};
}

Workload make_observe_workload(Size size) {
    const Sizes s = sizes_of(size);
    return observe_workload(realistic_kb(s.kb_size, 1000), realistic_generation(s.generation, 77),
                            s.batched_slice);
}

Workload make_uniform_workload(Size size) {
    const Sizes s = sizes_of(size);
    return observe_workload(uniform_kb(s.uniform_kb, 5), uniform_generation(s.uniform_policies, 6),
                            s.uniform_policies);
}

struct LoadState {
    std::vector<float> values;
    std::vector<kb::SegmentRecord> records;
};

std::shared_ptr<LoadState> load_state(std::size_t segments) {
    auto state = std::make_shared<LoadState>();
    const std::size_t policies = (segments + kSegmentsPerPolicy - 1) / kSegmentsPerPolicy;
    state->values = synthetic_behaviours(31, policies, kSteps);
    state->values.resize(segments * kDim);
    state->records.assign(segments, kb::SegmentRecord{0.25, 2, {0, 1}, {0, 3}});
    return state;
}

Workload make_load_workload(Size size) {
    auto state = load_state(sizes_of(size).load);
    Work baseline = [state] {
        std::vector<float> values(state->values);
        std::vector<kb::SegmentRecord> records(state->records);
        return static_cast<std::uint64_t>(records.size() + (values.empty() ? 1 : 0));
    };
    Work candidate = [state] {
        const kb::KnowledgeBase kb = kb::KnowledgeBase::from_segments(
            paper_params(), {kb::Source{"load", 0, 3, 1}}, state->values, state->records);
        return static_cast<std::uint64_t>(kb.size());
    };
    return Workload{baseline, candidate};
}

}  // namespace

void add_kb_cases(Registry& registry) {
    registry.add(
        Case{"kb", "segments",
             "one generation's observe step (200 x 200 segments of 300 values, KB of 32,580, with inserts): "
             "exact index vs batched brute force",
             50.0, make_observe_workload});
    registry.add(
        Case{"kb-uniform", "segments",
             "observe on uniform random segments (nothing prunes): index with its brute-force fallback vs "
             "batched brute force",
             1.0, make_uniform_workload});
    registry.add(Case{"kb-load", "segments",
                      "a KB of 10^6 segments from arrays (checks, copy, index build) vs copying the arrays",
                      0.1, make_load_workload});
    add_kb_flann_case(registry);
}

KbQueries kb_queries(Size size) {
    const Sizes s = sizes_of(size);
    return KbQueries{realistic_kb(s.kb_size, 1000), realistic_generation(s.generation, 77).values};
}

KbMeasurements measure_kb(Size size) {
    const Sizes s = sizes_of(size);
    KbMeasurements m;

    // realistic data: one generation with the index, slices with brute force
    {
        const kb::KnowledgeBase base = realistic_kb(s.kb_size, 1000);
        const Generation g = realistic_generation(s.generation, 77);
        m.kb_size = base.size();
        m.queries = g.queries();
        m.bytes_per_segment = base.bytes_per_segment();
        kb::KnowledgeBase kb = base;
        const auto start = Clock::now();
        m.inserted = observe_with_index(kb, g, g.policies);
        m.observe_seconds = seconds_since(start);
        m.index_queries_per_s = static_cast<double>(m.queries) / m.observe_seconds;
        m.candidates_per_query = static_cast<double>(kb.index().stats().candidates) /
                                 static_cast<double>(kb.index().stats().queries);

        reference::BruteKb brute(base);
        const auto t = Clock::now();
        for (std::size_t p = 0; p < s.batched_slice; ++p)
            brute.observe_batched(g.policy(p), kSegmentsPerPolicy, g.rewards[p]);
        m.batched_queries_per_s =
            static_cast<double>(s.batched_slice * kSegmentsPerPolicy) / seconds_since(t);
    }

    // uniform data
    {
        const kb::KnowledgeBase base = uniform_kb(s.uniform_kb, 5);
        const Generation g = uniform_generation(s.uniform_policies, 6);
        kb::KnowledgeBase kb = base;
        auto t = Clock::now();
        observe_with_index(kb, g, g.policies);
        m.uniform_index_queries_per_s = static_cast<double>(g.queries()) / seconds_since(t);
        reference::BruteKb brute(base);
        t = Clock::now();
        for (std::size_t p = 0; p < g.policies; ++p)
            brute.observe_batched(g.policy(p), kSegmentsPerPolicy, g.rewards[p]);
        m.uniform_batched_queries_per_s = static_cast<double>(g.queries()) / seconds_since(t);
    }

    // loading
    {
        const auto state = load_state(s.load);
        m.load_segments = s.load;
        auto t = Clock::now();
        {
            const std::vector<float> values(state->values);
            const std::vector<kb::SegmentRecord> records(state->records);
            m.copy_seconds = seconds_since(t);
        }
        t = Clock::now();
        const kb::KnowledgeBase kb = kb::KnowledgeBase::from_segments(
            paper_params(), {kb::Source{"load", 0, 3, 1}}, state->values, state->records);
        m.load_seconds = seconds_since(t);
    }
    return m;
}

}  // namespace stepstone::bench
