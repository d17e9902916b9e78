#include "exp/parallel/mpi.hpp"

#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstring>
#include <fstream>
#include <thread>

#include "core/error.hpp"
#include "core/text.hpp"

#if STEPSTONE_HAVE_MPI
#include <mpi.h>
#endif

namespace stepstone::mpi {

namespace {

// true when process `pid` of this host has ended (gone, or a zombie not yet reaped)
bool process_ended(pid_t pid) {
    if (::kill(pid, 0) != 0 && errno == ESRCH) return true;
    std::ifstream stat(concat("/proc/", pid, "/stat"));
    std::string text((std::istreambuf_iterator<char>(stat)), std::istreambuf_iterator<char>());
    const auto close = text.rfind(')');
    return close != std::string::npos && close + 2 < text.size() && text[close + 2] == 'Z';
}

std::string host_name() {
    char name[256] = {};
    ::gethostname(name, sizeof name - 1);
    return name;
}

}  // namespace

void require_built() {
    if (!built()) {
        throw ConfigError(
            concat(option_name("mpi"),
                   ": this stepstone was built without Open MPI (install libopenmpi-dev and rebuild)"));
    }
}

void Session::pause(int polls) {
    // the first polls are quick (a reply is often on its way), then 1 ms apart
    std::this_thread::sleep_for(std::chrono::microseconds(polls < 50 ? 50 : 1000));
}

std::vector<int> Session::lost_ranks() const {
    std::vector<int> lost;
    const std::string here = host_name();
    for (int r = 0; r < size_; ++r) {
        if (r != rank_ && peers_[static_cast<std::size_t>(r)].host == here &&
            process_ended(peers_[static_cast<std::size_t>(r)].pid)) {
            lost.push_back(r);
        }
    }
    return lost;
}

std::string Session::describe(int rank) const {
    const auto& peer = peers_.at(static_cast<std::size_t>(rank));
    return concat("rank ", rank, " (pid ", peer.pid, " on ", peer.host, ")");
}

#if STEPSTONE_HAVE_MPI

namespace {

void check(int code, const char* call) {
    if (code == MPI_SUCCESS) return;
    char text[MPI_MAX_ERROR_STRING] = {};
    int length = 0;
    MPI_Error_string(code, text, &length);
    throw Error(concat("MPI: ", call, " failed: ", std::string(text, static_cast<std::size_t>(length))));
}

struct PeerRecord {
    char host[256];
    std::int64_t pid;
};

}  // namespace

bool built() { return true; }

struct Session::Posted {
    std::string bytes;
    MPI_Request request = MPI_REQUEST_NULL;
};

Session::Session() {
    int initialised = 0;
    MPI_Initialized(&initialised);
    if (initialised) throw Error("MPI: a session is already open in this process");
    if (MPI_Init(nullptr, nullptr) != MPI_SUCCESS) throw Error("MPI: MPI_Init failed");
    MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
    check(MPI_Comm_rank(MPI_COMM_WORLD, &rank_), "MPI_Comm_rank");
    check(MPI_Comm_size(MPI_COMM_WORLD, &size_), "MPI_Comm_size");
    PeerRecord mine{};
    std::strncpy(mine.host, host_name().c_str(), sizeof mine.host - 1);
    mine.pid = ::getpid();
    std::vector<PeerRecord> all(static_cast<std::size_t>(size_));
    check(MPI_Allgather(&mine, sizeof mine, MPI_BYTE, all.data(), sizeof mine, MPI_BYTE, MPI_COMM_WORLD),
          "MPI_Allgather");
    for (const auto& record : all) peers_.push_back({record.host, static_cast<pid_t>(record.pid)});
}

Session::~Session() {
    if (abandoned_) return;
    try {
        flush();  // the stop messages of a job that ended early may still be on their way
    } catch (const Error&) {
        // a rank is gone: mpirun ends the job
    }
    MPI_Finalize();
}

void Session::complete(void* request, const char* call) {
    auto* handle = static_cast<MPI_Request*>(request);
    for (int polls = 0;; ++polls) {
        int done = 0;
        check(MPI_Test(handle, &done, MPI_STATUS_IGNORE), call);
        if (done) return;
        if (cancel_ && cancel_()) {
            MPI_Cancel(handle);  // best effort: the job is ending
            throw Cancelled();
        }
        pause(polls);
    }
}

void Session::send(int dest, int tag, std::string_view bytes) {
    MPI_Request request;
    check(MPI_Isend(bytes.data(), static_cast<int>(bytes.size()), MPI_BYTE, dest, tag, MPI_COMM_WORLD,
                    &request),
          "MPI_Isend");
    complete(&request, "MPI_Isend");
}

void Session::post(int dest, int tag, std::string bytes) {
    Posted& posted = posted_.emplace_back();
    posted.bytes = std::move(bytes);
    const int code = MPI_Isend(posted.bytes.data(), static_cast<int>(posted.bytes.size()), MPI_BYTE, dest,
                               tag, MPI_COMM_WORLD, &posted.request);
    if (code != MPI_SUCCESS) posted_.pop_back();
    check(code, "MPI_Isend");
    progress();
}

void Session::progress() {
    for (auto it = posted_.begin(); it != posted_.end();) {
        int done = 0;
        check(MPI_Test(&it->request, &done, MPI_STATUS_IGNORE), "MPI_Isend");
        it = done ? posted_.erase(it) : std::next(it);
    }
}

void Session::flush() {
    while (!posted_.empty()) {
        complete(&posted_.front().request, "MPI_Isend");
        posted_.pop_front();
    }
}

std::optional<Envelope> Session::poll() {
    progress();
    int flag = 0;
    MPI_Status status;
    check(MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &status), "MPI_Iprobe");
    if (!flag) return std::nullopt;
    return Envelope{status.MPI_SOURCE, status.MPI_TAG};
}

Message Session::receive(const Envelope& envelope) {
    MPI_Status status;
    int flag = 0;
    check(MPI_Iprobe(envelope.source, envelope.tag, MPI_COMM_WORLD, &flag, &status), "MPI_Iprobe");
    if (!flag) throw Error("MPI: the message to receive is gone (internal)");
    int count = 0;
    check(MPI_Get_count(&status, MPI_BYTE, &count), "MPI_Get_count");
    Message message{envelope.source, envelope.tag, std::string(static_cast<std::size_t>(count), '\0')};
    MPI_Request request;
    check(MPI_Irecv(message.bytes.data(), count, MPI_BYTE, envelope.source, envelope.tag, MPI_COMM_WORLD,
                    &request),
          "MPI_Irecv");
    complete(&request, "MPI_Irecv");
    return message;
}

#else  // built without Open MPI: no session can be opened

bool built() { return false; }

struct Session::Posted {};

Session::Session() { require_built(); }
void Session::complete(void*, const char*) {}
Session::~Session() = default;
void Session::send(int, int, std::string_view) { require_built(); }
void Session::post(int, int, std::string) { require_built(); }
void Session::flush() {}
void Session::progress() {}
std::optional<Envelope> Session::poll() { return std::nullopt; }
Message Session::receive(const Envelope&) {
    require_built();
    return {};
}

#endif

}  // namespace stepstone::mpi
