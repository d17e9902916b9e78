#pragma once

// The Open MPI transport: a thin layer over the MPI C API that moves byte
// strings between the ranks of MPI_COMM_WORLD. Messages are polled
// (MPI_Iprobe) with short sleeps instead of blocking receives, so that a
// waiting rank leaves its core to the ranks that compute, and so that a
// signal (mpirun ending the job) is noticed at once. The binary may be built
// without Open MPI: built() then says so and a Session cannot be opened.

#include <sys/types.h>

#include <functional>
#include <list>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/error.hpp"

namespace stepstone::mpi {

/// True when this binary was built with Open MPI.
bool built();

/// Throws ConfigError ("built without Open MPI ...") when built() is false.
void require_built();

/// Thrown by a send or receive that the session's cancel check ended (see
/// Session::set_cancel): the job is being torn down under this rank.
class Cancelled : public Error {
public:
    Cancelled() : Error("the MPI job is being stopped") {}
};

/// A message waiting to be received.
struct Envelope {
    int source = 0;
    int tag = 0;
};

/// A received message.
struct Message {
    int source = 0;
    int tag = 0;
    std::string bytes;
};

/// Where a rank runs, exchanged when the session opens.
struct Peer {
    std::string host;
    pid_t pid = 0;
};

/// MPI for this process, from MPI_Init to MPI_Finalize. At most one per
/// process. Errors of MPI calls are returned (MPI_ERRORS_RETURN) and thrown
/// as Error naming the call, instead of aborting the job.
class Session {
public:
    /// Initialises MPI and exchanges every rank's host and pid. Throws
    /// ConfigError when built without Open MPI, Error when MPI cannot start.
    Session();
    /// Finalizes MPI, unless abandon() was called (the job is being torn down).
    ~Session();
    Session(const Session&) = delete;
    Session& operator=(const Session&) = delete;

    int rank() const { return rank_; }
    int size() const { return size_; }
    const std::vector<Peer>& peers() const { return peers_; }

    /// Sends and receives are non-blocking underneath and wait by polling:
    /// while they wait, `cancel` is asked, and when it says true they give up
    /// with Cancelled. A peer that died mid-message would otherwise hold this
    /// rank forever.
    void set_cancel(std::function<bool()> cancel) { cancel_ = std::move(cancel); }

    /// Sends `bytes` to rank `dest` with `tag`; returns once they are on their way.
    void send(int dest, int tag, std::string_view bytes);
    /// Starts sending `bytes` and returns at once: the message goes on while
    /// this rank works, moved along by poll(), receive() and flush(). Two
    /// ranks that post to each other cannot block each other, as two send()s
    /// of large messages can. Messages to a rank arrive in the order sent.
    void post(int dest, int tag, std::string bytes);
    /// Waits until every posted message is on its way.
    void flush();
    /// The next message waiting (from any rank, any tag), if any.
    std::optional<Envelope> poll();
    /// Receives the waiting message `envelope` names.
    Message receive(const Envelope& envelope);
    /// Waits for the next message, polling and sleeping a little between
    /// polls. `keep_waiting` is called between polls; when it returns false
    /// the wait ends with nullopt.
    template <class KeepWaiting>
    std::optional<Message> wait(KeepWaiting keep_waiting) {
        for (int polls = 0;; ++polls) {
            if (auto envelope = poll()) return receive(*envelope);
            if (!keep_waiting()) return std::nullopt;
            pause(polls);
        }
    }

    /// The ranks (other than this one) on this host whose process is gone:
    /// after mpirun began ending the job, the rank that died.
    std::vector<int> lost_ranks() const;
    /// "rank R (pid P on HOST)".
    std::string describe(int rank) const;

    /// Skips MPI_Finalize in the destructor: the job is ending without the
    /// other ranks, which would never reach it.
    void abandon() { abandoned_ = true; }

    /// Sleeps between two polls that found nothing: briefly for the first
    /// `polls` (a reply is often on its way), then 1 ms.
    static void pause(int polls);

private:
    // polls `request` (an MPI_Request) to completion, giving up with Cancelled
    void complete(void* request, const char* call);
    // forgets the posted messages that are on their way
    void progress();

    struct Posted;  // a posted message: its bytes and request
    std::list<Posted> posted_;
    int rank_ = 0;
    int size_ = 1;
    std::vector<Peer> peers_;
    bool abandoned_ = false;
    std::function<bool()> cancel_;
};

}  // namespace stepstone::mpi
