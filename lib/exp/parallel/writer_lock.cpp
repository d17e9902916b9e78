#include "exp/parallel/writer_lock.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>

#include "core/error.hpp"
#include "core/text.hpp"

namespace stepstone {

namespace fs = std::filesystem;

namespace {

// this process's command line, arguments separated by spaces
std::string own_command() {
    std::ifstream in("/proc/self/cmdline", std::ios::binary);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    while (!text.empty() && text.back() == '\0') text.pop_back();
    for (char& c : text) {
        if (c == '\0' || c == '\n') c = ' ';
    }
    return text;
}

std::string read_holder(int fd) {
    std::string text(512, '\0');
    const ssize_t got = ::pread(fd, text.data(), text.size(), 0);
    text.resize(got > 0 ? static_cast<std::size_t>(got) : 0);
    while (!text.empty() && (text.back() == '\n' || text.back() == '\0')) text.pop_back();
    return one_line(text);
}

}  // namespace

fs::path WriterLock::lock_path(const fs::path& file) { return fs::path(file.string() + ".lock"); }

WriterLock::WriterLock(const fs::path& file) : lock_(lock_path(file)) {
    // the lock file is removed on release: a lock taken on a file that was
    // removed meanwhile is retaken on the new one
    for (int attempt = 0; attempt < 100; ++attempt) {
        const int fd = ::open(lock_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
        if (fd < 0) {
            throw Error(concat(file.string(), ": cannot create the writer lock ", lock_.string(), ": ",
                               std::strerror(errno)));
        }
        if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
            const int error = errno;
            const std::string holder = read_holder(fd);
            ::close(fd);
            if (error == EWOULDBLOCK) {
                throw Error(concat(file.string(), ": another process is writing it (",
                                   holder.empty() ? std::string("see ") + lock_.string() : holder,
                                   "); wait for it to finish or stop it, then retry"));
            }
            throw Error(concat(file.string(), ": cannot lock ", lock_.string(), ": ", std::strerror(error)));
        }
        struct stat held {};
        struct stat named {};
        if (::fstat(fd, &held) == 0 && ::stat(lock_.c_str(), &named) == 0 && held.st_ino == named.st_ino &&
            held.st_dev == named.st_dev) {
            fd_ = fd;
            const std::string holder = concat("pid ", ::getpid(), ": ", own_command(), "\n");
            if (::ftruncate(fd_, 0) == 0) {
                [[maybe_unused]] const ssize_t written = ::pwrite(fd_, holder.data(), holder.size(), 0);
            }
            return;
        }
        ::close(fd);  // the file was removed by the previous holder: retry on the new one
    }
    throw Error(concat(file.string(), ": cannot take the writer lock ", lock_.string()));
}

WriterLock::~WriterLock() {
    if (fd_ < 0) return;
    ::unlink(lock_.c_str());  // still holding it: nobody else holds this inode
    ::close(fd_);
}

// ------------------------------------------------------------ InterruptGuard

namespace {

volatile std::sig_atomic_t g_received = 0;
struct sigaction g_previous_int {};
struct sigaction g_previous_term {};

extern "C" void on_interrupt(int number) { g_received = number; }

}  // namespace

InterruptGuard::InterruptGuard() {
    g_received = 0;
    struct sigaction action {};
    action.sa_handler = on_interrupt;
    sigemptyset(&action.sa_mask);
    ::sigaction(SIGINT, &action, &g_previous_int);
    ::sigaction(SIGTERM, &action, &g_previous_term);
}

InterruptGuard::~InterruptGuard() {
    ::sigaction(SIGINT, &g_previous_int, nullptr);
    ::sigaction(SIGTERM, &g_previous_term, nullptr);
    g_received = 0;  // no guard, no interruption
}

int InterruptGuard::received() { return static_cast<int>(g_received); }

}  // namespace stepstone
