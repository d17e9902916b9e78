#pragma once

// A `stepstone serve` process started by a test, on a free loopback port.

#include <sys/types.h>

#include <filesystem>
#include <string>
#include <vector>

namespace stepstone::servicetest {

class ServerProcess {
public:
    /// Starts `stepstone serve <args> --port 0`, its output in `dir`, and
    /// waits (up to 30 s) for its "listening on" line. Throws if it exits first.
    ServerProcess(const std::vector<std::string>& args, const std::filesystem::path& dir);
    /// Stops it (SIGTERM) if still running.
    ~ServerProcess();
    ServerProcess(const ServerProcess&) = delete;
    ServerProcess& operator=(const ServerProcess&) = delete;

    int port() const { return port_; }
    pid_t pid() const { return pid_; }
    /// Sends SIGTERM and waits: the exit status (128 + signal if killed).
    int stop();
    std::string err() const;

private:
    pid_t pid_ = -1;
    int port_ = 0;
    std::filesystem::path out_, err_;
};

}  // namespace stepstone::servicetest
