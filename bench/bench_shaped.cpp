// `shaped-1.83`, `shaped-3.84`: one target-task generation shaped by `sum`
// (every child's r_max looked up in a KB a source run grew) against the same
// generation unshaped, the way a run pays for it.

#include "bench/bench_shaped.hpp"

#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "bench/cases.hpp"
#include "core/embedded.hpp"
#include "core/error.hpp"
#include "exp/evaluation.hpp"
#include "exp/evolution.hpp"
#include "kb/segments.hpp"
#include "sim/sensors.hpp"

namespace stepstone {
std::span<const EmbeddedFile> bench_fixture_files();  // generated from bench/data
}

namespace stepstone::bench {

namespace {

std::string_view fixture(std::string_view name) {
    for (const EmbeddedFile& file : bench_fixture_files())
        if (file.path == name) return file.text;
    throw DataError(std::string("bench fixture ") + std::string(name) + " is not embedded");
}

// the KB at `delta` grown from the fixture's source genomes (Size::quick:
// every fifth of them); built once per process and delta
const kb::KnowledgeBase& source_kb(Size size, double delta) {
    static std::vector<std::unique_ptr<std::pair<std::pair<Size, double>, kb::KnowledgeBase>>> built;
    for (const auto& entry : built)
        if (entry->first == std::make_pair(size, delta)) return entry->second;
    if (delta != kShapedDeltas[0]) {
        // a coarser KB is the finer one re-observed (`kb export --delta`)
        const kb::KnowledgeBase& fine = source_kb(size, kShapedDeltas[0]);
        built.push_back(std::make_unique<std::pair<std::pair<Size, double>, kb::KnowledgeBase>>(
            std::make_pair(size, delta), fine.coarsened(delta)));
        return built.back()->second;
    }
    std::vector<nn::Genome> genomes;
    std::istringstream lines{std::string(fixture("source_genomes.jsonl"))};
    std::size_t k = 0;
    for (std::string line; std::getline(lines, line); ++k)
        if (!line.empty() && (size == Size::full || k % 5 == 0))
            genomes.push_back(nn::Genome::from_json(nlohmann::json::parse(line)));

    const runs::EvolveConfig config;  // the source task of the paper's runs
    const auto task = sim::make_task(config.task);
    std::vector<float> behaviours;
    const auto evaluations = exp::evaluate_all(*task, genomes, config.dnn, 0, &behaviours);
    kb::KbParams params;
    params.delta = delta;
    kb::KnowledgeBase kb(params);
    const std::uint32_t source = kb.add_source("bench source run");
    const std::size_t width = task->behaviour_size();
    for (std::size_t i = 0; i < genomes.size(); ++i) {
        const std::span<const float> behaviour(behaviours.data() + i * width, width);
        kb.observe(kb::segment_behaviour(behaviour, sim::kChannels, params.segment_width),
                   evaluations[i].reward, {source, static_cast<std::int64_t>(i)});
    }
    built.push_back(std::make_unique<std::pair<std::pair<Size, double>, kb::KnowledgeBase>>(
        std::make_pair(size, delta), std::move(kb)));
    return built.back()->second;
}

// one side: a target-task run restored to the fixture's generation before
// each call, so every call evaluates the same children on one thread
Work side(Size size, const kb::KnowledgeBase* kb) {
    auto state = std::make_shared<nlohmann::json>(nlohmann::json::parse(fixture("generation.json")));
    // Size::quick: the first 12 members (whole evaluations: their diversity
    // compares trajectories of the stored length)
    if (size == Size::quick)
        state->at("population").erase(state->at("population").begin() + 12, state->at("population").end());
    runs::EvolveConfig config;
    config.task.kind = sim::TaskKind::target;
    config.ea.population_size = static_cast<int>(state->at("population").size());
    auto evolution = std::make_shared<exp::Evolution>(config, 11, 1);
    if (kb != nullptr) evolution->attach_shaping(*kb, runs::Treatment::sum);
    return [evolution, state] {
        evolution->restore(*state);
        return static_cast<std::uint64_t>(evolution->epoch().stats.evaluations);
    };
}

}  // namespace

ShapedKbShape shaped_kb_shape(Size size, double delta) {
    const kb::KnowledgeBase& kb = source_kb(size, delta);
    ShapedKbShape shape;
    shape.segments = kb.size();
    for (const kb::SegmentRecord& r : kb.records()) shape.positive += r.average() > 0 ? 1 : 0;
    return shape;
}

void add_shaped_cases(Registry& registry) {
    for (const double delta : kShapedDeltas) {
        const std::string name = delta == kShapedDeltas[0] ? "shaped-1.83" : "shaped-3.84";
        registry.add(Case{
            name, "evaluations",
            "one target-task generation (population 100, 12,000 steps an evaluation, diversity, "
            "selection) shaped by sum with a KB grown from 500 policies of a source run at delta " +
                std::string(delta == kShapedDeltas[0] ? "1.83" : "3.84") + " vs the same generation unshaped",
            0.8, [delta](Size size) {
                return Workload{side(size, nullptr), side(size, &source_kb(size, delta))};
            }});
    }
}

}  // namespace stepstone::bench
