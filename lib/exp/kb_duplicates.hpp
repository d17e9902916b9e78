#pragma once

#include <filesystem>
#include <span>
#include <vector>

#include "db/kb_store.hpp"

namespace stepstone::exp {

/// `kb merge` without --allow-duplicates: throws ConfigError when two of the
/// loaded inputs are the same file, hold the same KB (equal content digests)
/// or observed the same source run (same name, generations and policies), as
/// their policies would then count twice.
void refuse_duplicate_kbs(std::span<const std::filesystem::path> inputs, const std::vector<db::StoredKb>& loaded);

}  // namespace stepstone::exp
