#include "exp/campaign/campaign_cost.hpp"

#include <cstdio>

#include "core/progress.hpp"
#include "core/rng.hpp"
#include "core/text.hpp"
#include "exp/evaluation.hpp"
#include "nn/genome.hpp"

namespace stepstone::exp {

CampaignCost estimate_cost(const runs::CampaignConfig& config, double measure_seconds) {
    CampaignCost cost;
    auto add = [&](const runs::RunStep& step, std::size_t runs) {
        const auto& ea = step.config.ea;
        const std::int64_t per_run = static_cast<std::int64_t>(ea.initial_multiplier) * ea.population_size +
                                     static_cast<std::int64_t>(step.generations) * ea.population_size;
        const auto evaluations = per_run * static_cast<std::int64_t>(runs);
        cost.runs += static_cast<std::int64_t>(runs);
        cost.evaluations += evaluations;
        cost.robot_steps +=
            static_cast<double>(evaluations) * step.config.task.starts * step.config.task.steps_per_start;
    };
    if (config.source) add(*config.source, config.source->seeds.size());
    add(config.target, config.target.seeds.size() * config.treatments.size());

    // full-length episodes of random perceptrons (no stand-still stop), on one core
    sim::TaskConfig task = config.target.config.task;
    task.still_limit = task.steps_per_start * task.starts + 1;
    const auto shared = sim::make_task(task);
    const double started = now_seconds();
    double steps = 0;
    for (std::uint64_t k = 0; steps == 0 || now_seconds() - started < measure_seconds; ++k) {
        Rng rng(0, 0, k, Purpose::initial_genome);
        auto genome = nn::Genome::random_perceptron(config.target.config.dnn, rng);
        genome.simplify();
        steps += static_cast<double>(evaluate_genome(*shared, genome, config.target.config.dnn).steps);
    }
    cost.steps_per_second = steps / (now_seconds() - started);
    cost.cpu_seconds = cost.robot_steps / cost.steps_per_second;
    return cost;
}

void write_plan(std::ostream& out, const runs::CampaignConfig& config, const CampaignCost& cost,
                unsigned jobs) {
    const unsigned workers = resolve_threads(jobs);
    if (config.source) {
        out << "source   " << config.source->seeds.size() << " runs x " << config.source->generations
            << " generations (population " << config.source->config.ea.population_size << ")\n";
    }
    switch (config.kb_from) {
        case runs::KbFrom::best:
            out << "kb       export of the best source run's KB\n";
            break;
        case runs::KbFrom::merge:
            out << "kb       merge of every source run's KB\n";
            break;
        case runs::KbFrom::file:
            out << "kb       copy of " << config.kb_file_given << "\n";
            break;
    }
    if (config.kb_delta) out << "         coarsened to delta " << shortest(*config.kb_delta) << "\n";
    if (config.needs_randomized_kb())
        out << "kb-rand  randomized with seed " << config.randomize_seed << "\n";
    out << "target   " << config.treatments.size() << " treatments (";
    for (std::size_t k = 0; k < config.treatments.size(); ++k) {
        out << (k ? ", " : "") << to_string(config.treatments[k]);
    }
    out << ") x " << config.target.seeds.size() << " seeds x " << config.target.generations
        << " generations (population " << config.target.config.ea.population_size << ")\n";
    char line[512];
    std::snprintf(line, sizeof line,
                  "cost     %lld runs, %lld evaluations, at most %.3g robot steps\n"
                  "         at %.3g steps/s per core (measured now): at most %s of CPU, %s on %u jobs\n"
                  "         (an upper bound: policies that stand still stop early; diversity and KB time not "
                  "counted)\n",
                  static_cast<long long>(cost.runs), static_cast<long long>(cost.evaluations),
                  cost.robot_steps, cost.steps_per_second, format_duration(cost.cpu_seconds).c_str(),
                  format_duration(cost.cpu_seconds / workers).c_str(), workers);
    out << line;
}

}  // namespace stepstone::exp
