#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace stepstone::bench {

/// One side of a case: does a fixed amount of work and returns how many units
/// (steps, evaluations, pairs) it did. Called many times; it must leave its
/// state ready for the next call.
using Work = std::function<std::uint64_t()>;

/// The two callables of a case, built once before timing starts (maps,
/// networks and data are prepared by the case, outside the timed region).
struct Workload {
    Work baseline;   ///< the reference implementation (the original's way)
    Work candidate;  ///< stepstone's implementation
};

/// How big a case's workload should be.
enum class Size {
    full,   ///< the paper's sizes (one generation, one whole evaluation)
    quick,  ///< a reduced amount of work per call, for `--quick` and ctest
};

/// A benchmark: a baseline and a candidate doing the same work, compared by
/// their throughput in the same process.
struct Case {
    std::string name;         ///< CLI name, e.g. "sim"
    std::string unit;         ///< what one unit of work is, e.g. "steps"
    std::string description;  ///< one line: what both sides do
    double target_ratio = 1;  ///< the ratio candidate/baseline the design aims for
    /// Builds the workload; called once per run of the case.
    std::function<Workload(Size)> make;
};

/// The list of cases `stepstone bench` knows, in registration order.
///
/// A case with a parameter (`serve` and its number of clients) is registered as
/// one row a value, named CASE/VALUE ("serve/2"): each row is timed and judged
/// on its own, and CASE alone names every row of it (select, and --target).
class Registry {
public:
    /// Adds a case. Throws std::invalid_argument if the name is empty or taken,
    /// or if it would make a name ambiguous: a row CASE/VALUE beside a case
    /// named CASE, or the reverse.
    void add(Case c);
    /// The case or row named `name`, or nullptr if there is none.
    const Case* find(std::string_view name) const;
    /// The case or row named `name`, or every row CASE/VALUE of the case `name`
    /// in registration order; empty if there is none.
    std::vector<const Case*> select(std::string_view name) const;
    /// Every case, in registration order.
    const std::vector<Case>& cases() const { return cases_; }
    /// The names of every case, in registration order.
    std::vector<std::string> names() const;

private:
    std::vector<Case> cases_;
};

/// A registry holding every case of cases.cpp's adders (the simulator, episode,
/// network, diversity, KB, shaped-run, evolve, evolved-population, MPI, render and serve cases).
/// Registration is explicit: this function calls each adder in turn.
Registry default_registry();

}  // namespace stepstone::bench
