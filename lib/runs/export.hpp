#pragma once

#include <filesystem>
#include <ostream>
#include <string>

namespace stepstone::runs {

/// What `stepstone export` writes, one row per...
enum class ExportWhat {
    generations,  ///< committed generation of each run
    individuals,  ///< evaluated individual of each run
    kb,           ///< segment of each knowledge base
};

/// Parses "generations", "individuals" or "kb"; ConfigError naming `what` otherwise.
ExportWhat parse_export_what(const std::string& text, const std::string& what);

/// Writes tidy CSV (one row per observation, one column per variable, a
/// header row; db/table_output.hpp's csv format) of a run file or of every
/// run of a campaign directory. Runs are told apart by leading columns
/// `task,treatment,seed` (for a campaign, its runs in plan order; pending
/// runs that have no file yet are skipped); `--what kb` writes the KBs of a
/// run file, or the campaign's KB files (leading column `file`). Inputs are
/// opened read-only. Returns the number of data rows.
std::size_t export_csv(const std::filesystem::path& input, ExportWhat what, std::ostream& out);

}  // namespace stepstone::runs
