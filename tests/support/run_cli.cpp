#include "support/run_cli.hpp"

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
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

// starts `command` with stdin from /dev/null and stdout/stderr into the files `out` and `err`
pid_t start_captured(const std::vector<std::string>& command, const std::filesystem::path& out_path,
                     const std::filesystem::path& err_path, const std::filesystem::path& cwd) {
    Argv argv(command.front(), std::vector<std::string>(command.begin() + 1, command.end()));
    const pid_t pid = ::fork();
    if (pid < 0) throw std::runtime_error("fork failed");
    if (pid == 0) {
        const int in = ::open("/dev/null", O_RDONLY);
        const int out = ::open(out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        const int err = ::open(err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        ::dup2(in, 0);
        ::dup2(out, 1);
        ::dup2(err, 2);
        if (!cwd.empty() && ::chdir(cwd.c_str()) != 0) ::_exit(127);
        ::execvp(argv.pointers[0], argv.pointers.data());
        ::_exit(127);
    }
    return pid;
}

CliResult captured_result(int status, const std::filesystem::path& out_path,
                          const std::filesystem::path& err_path) {
    CliResult result;
    result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    result.out = read_file(out_path);
    result.err = read_file(err_path);
    return result;
}

}  // namespace

CliResult run_cli(const std::vector<std::string>& args, const std::filesystem::path& cwd) {
    return run_program(Argv(args).storage, cwd);
}

CliResult run_program(const std::vector<std::string>& command, const std::filesystem::path& cwd) {
    TempDir capture;
    const pid_t pid = start_captured(command, capture / "out", capture / "err", cwd);
    int status = 0;
    ::waitpid(pid, &status, 0);
    return captured_result(status, capture / "out", capture / "err");
}

bool run_cli_killed_when(const std::vector<std::string>& args, const std::function<bool()>& ready,
                         std::chrono::seconds timeout) {
    Argv argv(args);
    const pid_t pid = ::fork();
    if (pid < 0) throw std::runtime_error("fork failed");
    if (pid == 0) {
        const int null = ::open("/dev/null", O_WRONLY);
        ::dup2(null, STDOUT_FILENO);
        ::dup2(null, STDERR_FILENO);
        ::execv(argv.pointers[0], argv.pointers.data());
        ::_exit(127);
    }
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    bool held = false;
    while (!(held = ready()) && std::chrono::steady_clock::now() < deadline) {
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    ::kill(pid, SIGKILL);
    int status = 0;
    ::waitpid(pid, &status, 0);
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
    const pid_t pid = start_captured(command, capture / "out", capture / "err", {});
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (!ready() && std::chrono::steady_clock::now() < deadline) {
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    if (while_running) while_running();
    const auto signalled = std::chrono::steady_clock::now();
    if (signal != 0) ::kill(pid, signal);
    int status = 0;
    ::waitpid(pid, &status, 0);
    if (seconds_to_exit) {
        *seconds_to_exit =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - signalled).count();
    }
    return captured_result(status, capture / "out", capture / "err");
}

std::vector<std::string> mpirun_command(int ranks, const std::vector<std::string>& args) {
    // CI runs as root, and has fewer cores than some tests have ranks
    std::vector<std::string> command{"mpirun", "--allow-run-as-root", "--oversubscribe",
                                     "-np",    std::to_string(ranks), STEPSTONE_BINARY};
    command.insert(command.end(), args.begin(), args.end());
    return command;
}

}  // namespace stepstone::test
