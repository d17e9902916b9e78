#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/progress.hpp"

namespace stepstone::report {

/// What `stepstone report` is asked for.
struct ReportOptions {
    std::filesystem::path input;  ///< a run file, or a campaign directory (holding campaign.db)
    std::filesystem::path out;    ///< the report directory to create
    bool force = false;           ///< replace an existing `out`
    double threshold = 0.5;       ///< success: best-of-run reward >= this (campaigns)
    std::optional<int> generation;  ///< campaigns: compare at this generation (default: the target budget)
    ProgressMode progress = ProgressMode::automatic;
};

/// What a report holds.
struct ReportSummary {
    std::filesystem::path index;      ///< out / "index.html"
    std::vector<std::string> files;   ///< every file written, relative to out
    std::vector<std::string> notes;   ///< what could not be shown, and why
};

/// Writes the report of a run file or a campaign directory into `out`:
/// index.html (self-contained: inline style, no script, figures as files
/// beside it) with every figure that applies, the statistics tables, the
/// configs, the knowledge bases and the provenance. Written atomically
/// (write_directory). Throws ConfigError for an existing `out` without
/// force, DatabaseError for a foreign or unreadable file, DataError for a run
/// with no generation or a campaign with nothing to show.
ReportSummary write_report(const ReportOptions& options);

}  // namespace stepstone::report
