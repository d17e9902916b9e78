#pragma once

// The output of `stepstone kb ...` and `stepstone shape`, text and JSON. The
// library (lib/exp/kb_*.hpp) computes; these functions only print.

#include <nlohmann/json.hpp>
#include <ostream>
#include <string>

#include "exp/kb_apply.hpp"
#include "exp/kb_calibrate.hpp"
#include "runs/kb_files.hpp"
#include "runs/kb_stats.hpp"

namespace stepstone::app {

/// "<file>: knowledge base "<name>", N segments (...)": what export, merge and randomize wrote.
void write_written(std::ostream& out, const std::string& file, const runs::KbWritten& kb);

/// The flag, "the run's knowledge base" or "default".
std::string width_source_text(exp::WidthSource source);
nlohmann::json to_json(const exp::RunCalibration& result);
void write_text(std::ostream& out, const exp::RunCalibration& result);

nlohmann::json to_json(const runs::KbStats& stats);
/// The text report: parameters, the histogram with a bar of '#', counts, provenance.
void write_text(std::ostream& out, const runs::KbStats& stats);

nlohmann::json to_json(const exp::Shaping& shaping);
void write_text(std::ostream& out, const exp::Shaping& shaping);

/// The one line of `kb annotate`.
void write_text(std::ostream& out, const std::string& run_file, const exp::Annotation& done);

}  // namespace stepstone::app
