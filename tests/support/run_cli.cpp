#include "support/run_cli.hpp"

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <optional>
#include <stdexcept>
#include <thread>

#include "support/temp_dir.hpp"

namespace stepstone::test {

std::vector<std::string> CliResult::err_lines() const {
    std::vector<std::string> lines;
    std::string line;
    for (char c : err) {
        if (c == '\n') {
            lines.push_back(line);
            line.clear();
        } else {
            line += c;
        }
    }
    if (!line.empty()) lines.push_back(line);
    return lines;
}

namespace {

// the binary and `args` as execv wants them (or a whole command line)
struct Argv {
    explicit Argv(const std::vector<std::string>& args) : Argv(STEPSTONE_BINARY, args) {}
    Argv(const std::string& program, const std::vector<std::string>& args) : storage{program} {
        storage.insert(storage.end(), args.begin(), args.end());
        for (auto& arg : storage) pointers.push_back(arg.data());
        pointers.push_back(nullptr);
    }
    std::vector<std::string> storage;
    std::vector<char*> pointers;
};

// Starts `command` (command[0] a path or a program in PATH), stdin from
// /dev/null, stdout and stderr to the given files (/dev/null when empty), in
// `cwd` unless empty; returns its pid.
pid_t spawn(const std::vector<std::string>& command, const std::filesystem::path& out_path,
            const std::filesystem::path& err_path, const std::filesystem::path& cwd = {}) {
    Argv argv(command.front(), std::vector<std::string>(command.begin() + 1, command.end()));
    const pid_t pid = ::fork();
    if (pid < 0) throw std::runtime_error("fork failed");
    if (pid == 0) {
        const auto open_output = [](const std::filesystem::path& path) {
            return path.empty() ? ::open("/dev/null", O_WRONLY)
                                : ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        };
        ::dup2(::open("/dev/null", O_RDONLY), STDIN_FILENO);
        ::dup2(open_output(out_path), STDOUT_FILENO);
        ::dup2(open_output(err_path), STDERR_FILENO);
        if (!cwd.empty() && ::chdir(cwd.c_str()) != 0) ::_exit(127);
        ::execvp(argv.pointers[0], argv.pointers.data());
        ::_exit(127);
    }
    return pid;
}

// Polls `ready()` every 5 ms until it holds or `timeout` passes; returns whether it held.
bool wait_until(const std::function<bool()>& ready, std::chrono::seconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    bool held = false;
    while (!(held = ready()) && std::chrono::steady_clock::now() < deadline) {
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return held;
}

// Reaps `pid`; the exit status (128 + signal if killed), its peak memory and
// the captured output. With `bound`, a process still running after it is
// killed and gets exit code -1.
CliResult reap(pid_t pid, const std::filesystem::path& out_path, const std::filesystem::path& err_path,
               std::optional<std::chrono::seconds> bound = std::nullopt) {
    int status = 0;
    struct rusage usage {};
    const bool exited =
        bound && wait_until([&] { return ::wait4(pid, &status, WNOHANG, &usage) == pid; }, *bound);
    const bool bounded_out = bound && !exited;
    if (bounded_out) ::kill(pid, SIGKILL);
    if (!exited) ::wait4(pid, &status, 0, &usage);
    CliResult result;
    result.exit_code = bounded_out ? -1 : WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    result.peak_rss_kib = usage.ru_maxrss;
    if (!out_path.empty()) result.out = read_file(out_path);
    if (!err_path.empty()) result.err = read_file(err_path);
    return result;
}

}  // namespace

CliResult run_cli(const std::vector<std::string>& args, const std::filesystem::path& cwd) {
    return run_program(Argv(args).storage, cwd);
}

CliResult run_cli_within(const std::vector<std::string>& args, std::chrono::seconds bound) {
    TempDir capture;
    const pid_t pid = spawn(Argv(args).storage, capture / "out", capture / "err");
    return reap(pid, capture / "out", capture / "err", bound);
}

CliResult run_program(const std::vector<std::string>& command, const std::filesystem::path& cwd) {
    TempDir capture;
    const pid_t pid = spawn(command, capture / "out", capture / "err", cwd);
    return reap(pid, capture / "out", capture / "err");
}

bool run_cli_killed_when(const std::vector<std::string>& args, const std::function<bool()>& ready,
                         std::chrono::seconds timeout) {
    const pid_t pid = spawn(Argv(args).storage, {}, {});
    const bool held = wait_until(ready, timeout);
    ::kill(pid, SIGKILL);
    reap(pid, {}, {});
    return held;
}

CliResult run_cli_signalled_when(const std::vector<std::string>& args, const std::function<bool()>& ready,
                                 const std::function<void()>& while_running, int signal,
                                 double* seconds_to_exit, std::chrono::seconds timeout) {
    return run_program_signalled_when(Argv(args).storage, ready, while_running, signal, seconds_to_exit,
                                      timeout);
}

CliResult run_program_signalled_when(const std::vector<std::string>& command,
                                     const std::function<bool()>& ready,
                                     const std::function<void()>& while_running, int signal,
                                     double* seconds_to_exit, std::chrono::seconds timeout) {
    TempDir capture;
    const pid_t pid = spawn(command, capture / "out", capture / "err");
    wait_until(ready, timeout);
    if (while_running) while_running();
    const auto signalled = std::chrono::steady_clock::now();
    if (signal != 0) ::kill(pid, signal);
    auto result = reap(pid, capture / "out", capture / "err");
    if (seconds_to_exit) {
        *seconds_to_exit =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - signalled).count();
    }
    return result;
}

std::vector<std::string> mpirun_command(int ranks, const std::vector<std::string>& args) {
    // CI runs as root, and has fewer cores than some tests have ranks
    std::vector<std::string> command{"mpirun", "--allow-run-as-root", "--oversubscribe",
                                     "-np",    std::to_string(ranks), STEPSTONE_BINARY};
    command.insert(command.end(), args.begin(), args.end());
    return command;
}

}  // namespace stepstone::test
