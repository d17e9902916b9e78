#include "server_process.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <regex>
#include <stdexcept>
#include <thread>

#include "support/temp_dir.hpp"

namespace stepstone::servicetest {

ServerProcess::ServerProcess(const std::vector<std::string>& args, const std::filesystem::path& dir)
    : out_(dir / "serve.out"), err_(dir / "serve.err") {
    std::vector<std::string> argv{STEPSTONE_BINARY, "serve"};
    argv.insert(argv.end(), args.begin(), args.end());
    argv.insert(argv.end(), {"--port", "0"});
    pid_ = fork();
    if (pid_ < 0) throw std::runtime_error("fork failed");
    if (pid_ == 0) {
        const int out = open(out_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        const int err = open(err_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        dup2(out, 1);
        dup2(err, 2);
        std::vector<char*> raw;
        for (auto& a : argv) raw.push_back(a.data());
        raw.push_back(nullptr);
        execv(raw[0], raw.data());
        _exit(127);
    }
    // http://127.0.0.1:P, or an IPv6 address bracketed: http://[::1]:P
    const std::regex listening(R"(listening on http://(?:\[[^\]]*\]|[^:/]+):(\d+))");
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    while (std::chrono::steady_clock::now() < deadline) {
        std::smatch match;
        const auto text = std::filesystem::exists(out_) ? test::read_file(out_) : std::string();
        if (std::regex_search(text, match, listening)) {
            port_ = std::stoi(match[1].str());
            return;
        }
        int status = 0;
        if (waitpid(pid_, &status, WNOHANG) == pid_) {
            pid_ = -1;
            throw std::runtime_error("serve exited before listening: " + err());
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    stop();
    throw std::runtime_error("serve did not listen within 30 s: " + err());
}

ServerProcess::~ServerProcess() {
    if (pid_ > 0) stop();
}

int ServerProcess::stop() {
    if (pid_ <= 0) return -1;
    kill(pid_, SIGTERM);
    int status = 0;
    waitpid(pid_, &status, 0);
    pid_ = -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

std::string ServerProcess::err() const {
    return std::filesystem::exists(err_) ? test::read_file(err_) : std::string();
}

}  // namespace stepstone::servicetest
