#pragma once

// Parts shared by the run and the campaign reports (report.cpp, report_campaign.cpp).

#include <filesystem>
#include <string>
#include <vector>

#include "db/kb_store.hpp"
#include "report/html.hpp"
#include "report/report.hpp"
#include "report/trace.hpp"

namespace stepstone::report {

/// `value` with `decimals` digits after the point.
std::string fixed(double value, int decimals);
/// About `rows` evenly spaced indices of [0, size), always with the first and the last.
std::vector<std::size_t> sample_indices(std::size_t size, std::size_t rows);
/// A KB's facts, provenance, histogram and growth; figure files start with `prefix`.
void add_kb_section(Page& page, const std::string& prefix, const db::StoredKb& stored, const std::string& origin);
/// A trajectory figure (SVG with hover titles) and, with a KB, its saliency along time.
void add_trajectory(Page& page, const std::string& name, const Trace& trace, const std::string& what);
/// Writes the page as `dir`/index.html and lists the report's files in `summary`.
void write_index(const Page& page, const std::filesystem::path& dir, ReportSummary& summary);
/// The campaign report (write_report for a directory), written into `dir`.
void campaign_report(const ReportOptions& options, const std::filesystem::path& dir, ReportSummary& summary);

}  // namespace stepstone::report
