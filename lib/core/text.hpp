#pragma once

#include <sstream>
#include <string>
#include <utility>

namespace stepstone {

/// Concatenates anything printable with operator<< into one string
/// (g++ 12 has no std::format). Doubles print with up to 17 significant digits.
template <class... Parts>
std::string concat(Parts&&... parts) {
    std::ostringstream out;
    out.precision(17);
    (out << ... << std::forward<Parts>(parts));
    return out.str();
}

/// The shortest text that reads back as `value` (1.83, not
/// 1.8300000000000001): for the values a user typed, in messages and reports.
std::string shortest(double value);

/// `value` with 17 significant digits ("%.17g"): reads back bit for bit, for CSV files.
std::string exact(double value);

/// Replaces newlines and carriage returns by "; " so a message stays on one line.
std::string one_line(std::string text);

}  // namespace stepstone
