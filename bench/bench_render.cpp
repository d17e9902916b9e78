// `render`: a trajectory figure of a 4,000-step policy with its KB lookups
// (replay, lookups, drawing, PNG encoding) against the replay alone.

#include <memory>
#include <vector>

#include "bench/cases.hpp"
#include "kb/segments.hpp"
#include "report/arena_figure.hpp"
#include "sim/controllers.hpp"
#include "sim/episode.hpp"

namespace stepstone::bench {

namespace {

struct RenderState {
    std::shared_ptr<const sim::Task> task;
    kb::KnowledgeBase kb{kb::KbParams{}};
    std::vector<float> behaviour;
};

// the source task on its first start (the 4,000 steps the KB describes), and
// a KB of the segments of random and scripted policies with made-up rewards
std::shared_ptr<RenderState> make_state(Size size) {
    auto state = std::make_shared<RenderState>();
    sim::TaskConfig config;
    config.starts = 1;
    state->task = sim::make_task(config);
    state->behaviour.resize(state->task->behaviour_size());
    const auto source = state->kb.add_source("bench");
    const int policies = size == Size::full ? 160 : 8;
    for (int p = 0; p < policies; ++p) {
        sim::RandomController random(static_cast<std::uint64_t>(p) + 1);
        sim::run_episode(*state->task, random, sim::Recording{state->behaviour, {}, nullptr});
        state->kb.observe(kb::segment_behaviour(state->behaviour, sim::kChannels, 20), (p % 5) / 24.0,
                          {source, p});
    }
    sim::ScriptedController scripted(sim::TaskKind::source);
    sim::run_episode(*state->task, scripted, sim::Recording{state->behaviour, {}, nullptr});
    state->kb.observe(kb::segment_behaviour(state->behaviour, sim::kChannels, 20), 0.5, {source, policies});
    return state;
}

}  // namespace

void add_render_cases(Registry& registry) {
    registry.add(
        Case{"render", "figures",
             "a trajectory figure of a 4,000-step scripted policy (replay, KB lookups of its 200 segments in "
             "a KB of ~30,000, drawing, PNG encoding) vs replaying it",
             0.03, [](Size size) {
                 auto state = make_state(size);
                 Work replay = [state] {
                     sim::ScriptedController policy(sim::TaskKind::source);
                     sim::run_episode(*state->task, policy, sim::Recording{state->behaviour, {}, nullptr});
                     return std::uint64_t{1};
                 };
                 Work render = [state] {
                     sim::ScriptedController policy(sim::TaskKind::source);
                     const auto trace = report::trace_episode(
                         state->task,
                         [&](const auto& observer) {
                             return sim::run_episode(*state->task, policy, sim::Recording{}, observer);
                         },
                         0, &state->kb, "bench", "the scripted policy");
                     report::ArenaLayout layout;
                     report::Canvas canvas(layout.width, layout.height, report::Format::png);
                     report::draw_trajectory(canvas, trace, {}, layout);
                     return std::uint64_t{!canvas.finish().empty()};
                 };
                 return Workload{replay, render};
             }});
}

}  // namespace stepstone::bench
