#pragma once

#include <filesystem>
#include <span>
#include <vector>

#include "core/error.hpp"
#include "db/kb_store.hpp"

namespace stepstone::runs {

/// Two inputs of a merge would count the same policies twice; what() says
/// which and why. The caller may offer a way to merge anyway.
class DuplicateKbs : public ConfigError {
public:
    using ConfigError::ConfigError;
};

/// A merge that does not allow duplicates: throws DuplicateKbs when two of the
/// loaded inputs are the same file, hold the same KB (equal content digests)
/// or observed the same source run (same name, generations and policies), as
/// their policies would then count twice.
void refuse_duplicate_kbs(std::span<const std::filesystem::path> inputs,
                          const std::vector<db::StoredKb>& loaded);

}  // namespace stepstone::runs
