#pragma once

// A tiny run for the engine's tests (evolution_test, run_evolve_test): 8
// individuals, one short start, fast enough for many runs per test.

#include <filesystem>
#include <string>

#include "core/progress.hpp"
#include "exp/evolution.hpp"
#include "support/temp_dir.hpp"

namespace stepstone::exptest {

inline constexpr const char* kTinyConfig = R"({
  "task": {"kind": "source", "steps_per_start": 300, "starts": 1},
  "ea": {"population_size": 8, "generations": 6},
  "dnn": {"add_connection_rate": 0.5, "add_neuron_rate": 0.3},
  "seed": 11
})";

/// Writes `text` as the config `name` in `dir`; returns its path.
inline std::filesystem::path write_config(const test::TempDir& dir, const std::string& text,
                                          const char* name = "c.json") {
    test::write_file(dir / name, text);
    return dir / name;
}

/// Options of a quiet run of dir/c.json into dir/db on `threads` threads.
inline exp::EvolveOptions options_for(const test::TempDir& dir, const std::string& db, unsigned threads) {
    exp::EvolveOptions options;
    options.config_path = dir / "c.json";
    options.db_path = dir / db;
    options.threads = threads;
    options.progress = ProgressMode::quiet;
    return options;
}

}  // namespace stepstone::exptest
