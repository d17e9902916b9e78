// `evolved`: the evaluations of an evolved population, as a run of the paper's
// source task pays for them, with "math": "portable" (every lane's move stepped
// together: sim::run_episode_queue's lanes) against "libm" (glibc's sine and
// cosine, one episode's step after another), in the same process.

#include <memory>
#include <string>
#include <vector>

#include "bench/cases.hpp"
#include "core/embedded.hpp"
#include "core/error.hpp"
#include "exp/evaluation.hpp"
#include "nn/genome.hpp"
#include "runs/evolve_config.hpp"
#include "sim/task.hpp"

namespace stepstone {
std::span<const EmbeddedFile> bench_fixture_files();  // generated from bench/data
}

namespace stepstone::bench {

namespace {

// The population of the checkpoint in bench/data/source_checkpoint.json (scripts/bench-fixture
// --source-checkpoint): a paper-size source run (examples/source_paper.json) at its last generation
std::vector<nn::Genome> evolved_population(Size size) {
    std::string_view text;
    for (const EmbeddedFile& file : bench_fixture_files())
        if (file.path == "source_checkpoint.json") text = file.text;
    if (text.empty()) throw DataError("bench fixture source_checkpoint.json is not embedded");
    const nlohmann::json state = nlohmann::json::parse(text);
    std::vector<nn::Genome> genomes;
    for (const nlohmann::json& member : state.at("population")) {
        genomes.push_back(nn::Genome::from_json(member.at("genome")));
        if (size == Size::quick && genomes.size() == 32) break;
    }
    return genomes;
}

// one side: the population evaluated on one thread as a generation evaluates it
Work side(std::shared_ptr<const std::vector<nn::Genome>> genomes, Math math) {
    runs::EvolveConfig config;  // the paper's source task
    config.task.math = math;
    std::shared_ptr<const sim::Task> task = sim::make_task(config.task);
    return [genomes, task, dnn = config.dnn] {
        exp::evaluate_all(*task, *genomes, dnn, 1, nullptr);
        return static_cast<std::uint64_t>(genomes->size());
    };
}

}  // namespace

void add_evolved_cases(Registry& registry) {
    registry.add(
        Case{"evolved", "evaluations",
             "the 200 policies of a paper-size source run's checkpoint (bench/data), evaluated on "
             "1 thread: portable math (lanes through the move) vs libm (scalar step)",
             1.0, [](Size size) {  // a guard: lanes never slower; issue 46 asks 1.54 (0.65x of the time)
                 auto genomes = std::make_shared<const std::vector<nn::Genome>>(evolved_population(size));
                 return Workload{side(genomes, Math::libm), side(genomes, Math::portable)};
             }});
}

}  // namespace stepstone::bench
