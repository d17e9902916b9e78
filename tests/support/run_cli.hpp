#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace stepstone::test {

/// What one run of the real stepstone binary did.
struct CliResult {
    int exit_code = -1;  ///< the exit status, or 128 + signal if killed
    std::string out;
    std::string err;
    /// stderr split into lines (no empty last line).
    std::vector<std::string> err_lines() const;
};

/// Runs the stepstone binary built with the tests with `args`, in `cwd`
/// (the current directory if empty), with no standard input.
CliResult run_cli(const std::vector<std::string>& args, const std::filesystem::path& cwd = {});

}  // namespace stepstone::test
