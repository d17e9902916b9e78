#pragma once

// CSV files as spreadsheets and statistics packages write them (RFC 4180):
// quoted fields, CRLF or LF line ends, a UTF-8 byte-order mark. The parsing is
// libcsv's; this adds the checks and the line numbers that messages need.

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace stepstone::runs {

/// One record of a CSV file: its fields (quotes removed, "" unescaped) and the
/// line of the file on which it ends (a quoted field may span lines).
struct CsvRecord {
    std::size_t line = 0;
    std::vector<std::string> fields;
};

/// Every record of `file`, blank lines skipped. Throws DataError naming the
/// file and the line for: an unreadable file, a carriage return that does not
/// end a line (outside quotes), and a quote that is never closed.
std::vector<CsvRecord> read_csv_records(const std::filesystem::path& file);

}  // namespace stepstone::runs
