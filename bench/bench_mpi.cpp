// `mpi`: whole generations of `evolve --mpi` on 2 ranks (mpirun -np 2)
// against the same run in one process on 2 threads. Both sides are this
// stepstone binary started afresh for every call, so both pay a start-up; the
// MPI side also pays mpirun's and MPI_Init's (~0.35 s here with the one-machine
// setting below, docs/scaling.md), which 16 generations after generation 0
// weigh as a short run would.

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>

#include "bench/cases.hpp"
#include "core/error.hpp"
#include "core/text.hpp"
#include "exp/parallel/child_process.hpp"
#include "exp/parallel/mpi.hpp"

namespace stepstone::bench {

namespace {

namespace fs = std::filesystem;

// a scratch folder with the run config, removed with the last side using it
struct Scratch {
    fs::path dir;
    fs::path program;
    int population = 0;
    int generations = 0;

    explicit Scratch(Size size) {
        std::string pattern = (fs::temp_directory_path() / "stepstone-bench-mpi-XXXXXX").string();
        if (::mkdtemp(pattern.data()) == nullptr) throw Error("bench mpi: cannot make a scratch folder");
        dir = pattern;
        program = fs::read_symlink("/proc/self/exe");
        // full: the paper's source task (population 200, 3 starts x 4000 steps)
        const bool full = size == Size::full;
        population = full ? 200 : 16;
        generations = full ? 16 : 3;
        std::ofstream(dir / "run.json")
            << concat(R"({"task": {"kind": "source", "steps_per_start": )", full ? 4000 : 500,
                      R"(, "starts": )", full ? 3 : 1, R"(}, "ea": {"population_size": )", population, "}}");
    }
    ~Scratch() {
        std::error_code ignored;
        fs::remove_all(dir, ignored);
    }
    Scratch(const Scratch&) = delete;
    Scratch& operator=(const Scratch&) = delete;
};

// the first line of `log` with words in it: mpirun states the problem before its banner lines
std::string first_words_of(const fs::path& log) {
    std::ifstream in(log);
    std::string line;
    while (std::getline(in, line)) {
        if (std::any_of(line.begin(), line.end(),
                        [](char c) { return std::isalpha(static_cast<unsigned char>(c)); })) {
            return line;
        }
    }
    return "no output";
}

// one side: a whole run of `generations` per call, in a fresh run file
Work side(std::shared_ptr<Scratch> scratch, bool mpi) {
    return [scratch, mpi] {
        const fs::path log = scratch->dir / (mpi ? "mpi.log" : "threads.log");
        std::vector<std::string> argv;
        // mpirun from PATH; as root (containers, CI) Open MPI refuses to start without its flag
        // one machine: Open MPI's point-to-point layer ob1 over shared memory; its default (UCX,
        // made for fast networks between nodes) adds 0.2 s to MPI_Init here
        if (mpi) argv = {"/usr/bin/env", "mpirun", "-np", "2", "--oversubscribe", "--mca", "pml", "ob1"};
        if (mpi && ::geteuid() == 0) argv.emplace_back("--allow-run-as-root");
        std::vector<std::string> evolve{scratch->program.string(),
                                        "evolve",
                                        "--config",
                                        (scratch->dir / "run.json").string(),
                                        "--db",
                                        (scratch->dir / (mpi ? "mpi.db" : "threads.db")).string(),
                                        "--force",
                                        "--seed",
                                        "3",
                                        "--generations",
                                        std::to_string(scratch->generations),
                                        "--threads",
                                        mpi ? "1" : "2",
                                        "--quiet"};
        if (mpi) evolve.emplace_back("--mpi");
        argv.insert(argv.end(), evolve.begin(), evolve.end());
        fs::remove(log);
        const int status = wait_child(spawn_child(argv, log));
        if (!exited_cleanly(status)) {
            throw Error(
                concat("bench mpi: ", mpi ? "mpirun -np 2 stepstone evolve --mpi" : "stepstone evolve",
                       " failed: ", describe_exit(status, first_words_of(log))));
        }
        // generation 0 evaluates twice the population (initial_multiplier 2), then one population a
        // generation
        return static_cast<std::uint64_t>(scratch->population) *
               static_cast<std::uint64_t>(2 + scratch->generations);
    };
}

}  // namespace

void add_mpi_cases(Registry& registry) {
    if (!mpi::built()) return;
    registry.add(
        Case{"mpi", "evaluations",
             "evolve of the source task (population 200, 12,000 steps an evaluation), generation 0 and 16 "
             "more, a fresh process a call: 2 MPI ranks (pml ob1) vs 1 process on 2 threads",
             0.9, [](Size size) {
                 auto scratch = std::make_shared<Scratch>(size);
                 return Workload{side(scratch, false), side(scratch, true)};
             }});
}

}  // namespace stepstone::bench
