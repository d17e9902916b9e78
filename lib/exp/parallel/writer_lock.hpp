#pragma once

#include <atomic>
#include <filesystem>
#include <string>

namespace stepstone {

/// One writer per file: an advisory flock(2) on `FILE.lock` beside the file,
/// held for the writer's lifetime and released (the lock file removed) by the
/// destructor or when the process dies, even by SIGKILL. The lock file holds
/// the holder's pid and command, so a refused writer names it. Readers never
/// take it. Taken by evolve (on the run file), campaign (on campaign.db),
/// kb annotate and db migrate.
class WriterLock {
public:
    /// Takes the lock at once or throws Error "<file>: <pid and command> is
    /// writing it ...". `file`'s folder must exist.
    explicit WriterLock(const std::filesystem::path& file);
    ~WriterLock();
    WriterLock(const WriterLock&) = delete;
    WriterLock& operator=(const WriterLock&) = delete;

    /// The lock file beside `file`.
    static std::filesystem::path lock_path(const std::filesystem::path& file);

private:
    std::filesystem::path lock_;
    int fd_ = -1;
};

/// SIGINT and SIGTERM set a flag instead of ending the process, so a long
/// writer stops at its next safe point. The handlers are restored by the
/// destructor.
class InterruptGuard {
public:
    InterruptGuard();
    ~InterruptGuard();
    InterruptGuard(const InterruptGuard&) = delete;
    InterruptGuard& operator=(const InterruptGuard&) = delete;

    /// The signal received (SIGINT or SIGTERM) while a guard lives, 0 if none.
    static int received();
};

}  // namespace stepstone
