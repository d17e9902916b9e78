#include "exp/parallel/child_process.hpp"

#include <fcntl.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <fstream>

#include "core/error.hpp"
#include "core/text.hpp"

namespace stepstone {

pid_t spawn_child(const std::vector<std::string>& args, const std::filesystem::path& log) {
    std::vector<std::string> storage = args;
    std::vector<char*> argv;
    for (auto& arg : storage) argv.push_back(arg.data());
    argv.push_back(nullptr);

    const pid_t parent = ::getpid();
    std::fflush(nullptr);
    const pid_t pid = ::fork();
    if (pid < 0) throw Error("cannot start a child process: fork failed");
    if (pid == 0) {
        // SIGKILL, not SIGTERM: a stepstone child takes SIGTERM as "stop after this generation"
        // and would keep its writer lock that long, refusing a parent restarted at once
        ::prctl(PR_SET_PDEATHSIG, SIGKILL);
        if (::getppid() != parent) ::_exit(125);  // the parent died before prctl
        const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
        if (fd >= 0) {
            ::dup2(fd, STDOUT_FILENO);
            ::dup2(fd, STDERR_FILENO);
            ::close(fd);
        }
        ::execv(argv[0], argv.data());
        ::_exit(127);
    }
    return pid;
}

int wait_child(pid_t pid) {
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    return status;
}

std::vector<ChildExit> reap_children() {
    std::vector<ChildExit> ended;
    for (;;) {
        int status = 0;
        const pid_t pid = ::waitpid(-1, &status, WNOHANG);
        if (pid <= 0) break;
        ended.push_back({pid, status});
    }
    return ended;
}

bool stopped_on_request(int status) {
    if (WIFSIGNALED(status)) return WTERMSIG(status) == SIGTERM || WTERMSIG(status) == SIGINT;
    return WIFEXITED(status) && WEXITSTATUS(status) == kExitStopped;
}

bool exited_cleanly(int status) { return WIFEXITED(status) && WEXITSTATUS(status) == 0; }

std::string describe_exit(int status, const std::string& fallback) {
    return WIFSIGNALED(status) ? concat("killed by signal ", WTERMSIG(status)) : fallback;
}

std::string last_line_of(const std::filesystem::path& path) {
    std::ifstream in(path);
    std::string line, last;
    while (std::getline(in, line)) {
        if (!line.empty()) last = line;
    }
    return last.empty() ? std::string("no output") : last;
}

}  // namespace stepstone
