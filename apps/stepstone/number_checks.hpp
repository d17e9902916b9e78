#pragma once

#include <CLI/CLI.hpp>

namespace stepstone::app {

/// Adds to every integer option of `app` and its subcommands (CLI11 type names
/// INT and UINT) a check of the text as given: a whole number in decimal
/// digits, within the option's type, and not negative for an unsigned one.
/// Without it CLI11 wraps "-4" to 2^64 - 4, saturates "1e23" and answers
/// "Could not convert" for "1e3". Failures are one line naming the option.
void check_whole_numbers(CLI::App& app);

}  // namespace stepstone::app
