#pragma once

#include <sys/types.h>

#include <filesystem>
#include <string>
#include <vector>

namespace stepstone {

/// Starts `argv[0]` (a path, not searched in PATH) with `argv` as a child
/// process whose stdout and stderr are appended to `log`. The child is sent
/// SIGKILL when this process dies, so a killed parent leaves no child working
/// behind its back. Returns the child's pid; throws Error if fork fails (a
/// failed exec ends the child with status 127).
pid_t spawn_child(const std::vector<std::string>& argv, const std::filesystem::path& log);

/// One child that ended.
struct ChildExit {
    pid_t pid = 0;
    int status = 0;  ///< as waitpid reports it
};

/// Waits for the child `pid` to end and returns its status (as waitpid
/// reports it).
int wait_child(pid_t pid);

/// Reaps every child that has ended by now, without waiting.
std::vector<ChildExit> reap_children();

/// True when `status` (from waitpid) is a normal exit with code 0.
bool exited_cleanly(int status);

/// The exit code of a stepstone command stopped by SIGINT or SIGTERM at a
/// safe point (its work committed, a resume continues it).
inline constexpr int kExitStopped = 130;

/// True when `status` (from waitpid) is such a stop, exit code kExitStopped,
/// or an end by SIGTERM or SIGINT (a signal that came before the child took
/// them: it had written nothing yet).
bool stopped_on_request(int status);

/// Why a child ended, for a failure message: "killed by signal N" when a
/// signal ended it, otherwise `fallback`.
std::string describe_exit(int status, const std::string& fallback);

/// The last non-empty line of the text file `path`, or "no output".
std::string last_line_of(const std::filesystem::path& path);

}  // namespace stepstone
