#pragma once

// Seeding: a run's generation 0 starts from policies of a finished source run
// (transfer.seed; docs/transfer.md: seeding), read and checked before the run
// file is written.

#include <cstdint>
#include <vector>

#include "nn/genome.hpp"
#include "runs/evolve_config.hpp"

namespace stepstone::exp {

/// The policies that seed a run's generation 0, in the order they enter it.
struct Seeds {
    std::vector<nn::Genome> genomes;
    std::vector<std::int64_t> source_ids;  ///< their individual ids in the source run
};

/// Reads the seeds of `config`'s transfer.seed from its source run file: the
/// candidates of `with` (the latest checkpoint's population, its first front,
/// or the stored genomes), ordered by task reward, highest first, the lower
/// source individual id on ties, of which the first min(count,
/// ea.population_size) are taken. Refuses, naming the file, a missing file
/// (DatabaseError), a run that is not finished, networks of other inputs or
/// outputs, a population of another size under `population`, and a source
/// whose db::run_digest differs from seed.digest when set (ConfigError).
/// Records the digest in seed.digest and makes seed.from absolute.
Seeds load_seeds(runs::EvolveConfig& config);

/// On the resume of a run whose generation 0 is committed, which needs no
/// seed any more: a source file still at seed.from must have the stored
/// seed.digest (ConfigError naming both digests otherwise); a missing one is
/// not looked for. Makes seed.from absolute.
void check_seed_source(runs::EvolveConfig& config);

}  // namespace stepstone::exp
