#pragma once

#include <chrono>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace stepstone::test {

/// What one run of the real stepstone binary did.
struct CliResult {
    int exit_code =
        -1;  ///< the exit status, or 128 + signal if killed (-1: killed at run_cli_within's bound)
    std::string out;
    std::string err;
    long peak_rss_kib = 0;  ///< the process's peak resident set size (wait4's ru_maxrss)
    /// stderr split into lines (no empty last line).
    std::vector<std::string> err_lines() const;
};

/// Runs the stepstone binary built with the tests with `args`, in `cwd`
/// (the current directory if empty), with no standard input.
CliResult run_cli(const std::vector<std::string>& args, const std::filesystem::path& cwd = {});

/// run_cli with a time bound: a run still going after `bound` is killed
/// (SIGKILL) and gets exit_code -1.
CliResult run_cli_within(const std::vector<std::string>& args, std::chrono::seconds bound);

/// Starts the stepstone binary with `args` (output discarded), waits until
/// `ready()` holds (polled every 5 ms, at most `timeout`), kills it with
/// SIGKILL and reaps it: a crash at an arbitrary moment. Returns whether
/// `ready()` held before the kill.
bool run_cli_killed_when(const std::vector<std::string>& args, const std::function<bool()>& ready,
                         std::chrono::seconds timeout = std::chrono::seconds(120));

/// Starts the stepstone binary with `args`, waits until `ready()` holds
/// (polled every 5 ms, at most `timeout`), calls `while_running()` (e.g. to
/// start a second process), sends `signal` (0: none) and waits for the end.
/// `seconds_to_exit` receives the time from the signal to the exit.
CliResult run_cli_signalled_when(const std::vector<std::string>& args, const std::function<bool()>& ready,
                                 const std::function<void()>& while_running, int signal,
                                 double* seconds_to_exit = nullptr,
                                 std::chrono::seconds timeout = std::chrono::seconds(120));

/// run_cli for any command line: `command[0]` is a path or a program
/// searched in PATH (e.g. mpirun_command's).
CliResult run_program(const std::vector<std::string>& command, const std::filesystem::path& cwd = {});

/// run_cli_signalled_when for any command line.
CliResult run_program_signalled_when(const std::vector<std::string>& command,
                                     const std::function<bool()>& ready,
                                     const std::function<void()>& while_running, int signal,
                                     double* seconds_to_exit = nullptr,
                                     std::chrono::seconds timeout = std::chrono::seconds(120));

/// `mpirun -np ranks` of the stepstone binary with `args`, oversubscribed
/// and allowed to run as root (CI).
std::vector<std::string> mpirun_command(int ranks, const std::vector<std::string>& args);

}  // namespace stepstone::test
