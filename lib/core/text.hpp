#pragma once

#include <functional>
#include <sstream>
#include <string>
#include <string_view>
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

/// How a library message names an option of the call it refuses: the option's
/// name in the call's options struct between backquotes (`force`). The library
/// speaks of its own options, never of a front end's flags; a front end spells
/// them its own way with `spell_options` (the CLI: --force).
inline std::string option_name(std::string_view name) { return concat('`', name, '`'); }

/// `message` with every option named by `option_name` (a backquoted name of
/// lower-case letters, digits and underscores) replaced by `spell(name)`; the
/// rest of the text as it is.
std::string spell_options(std::string_view message,
                          const std::function<std::string(std::string_view)>& spell);

/// Replaces newlines and carriage returns by "; " so a message stays on one line.
std::string one_line(std::string text);

}  // namespace stepstone
