#pragma once
// MRPT's deserialization of the classes the rawlog reader does not parse (rawlog_entries.h), run in a child process.
//
// Why: those objects carry no length, so only their own serializeFrom() knows where they end, and MRPT trusts the
// file: a lying length field allocates gigabytes, libjpeg's error handler calls exit(1), other paths crash. In a
// child, any of that ends the child, not the program; the parent turns it into an InputError.
//
// How: the child is forked on the first such object of a rawlog and kept for the later ones (a new one is forked
// when it has died). It reads the object with MRPT from a CStream whose Read() asks the parent for bytes over a
// socket, 64 KiB per request (the first 64 KiB come with the command: one round trip for most objects); the parent
// answers from its RawlogStream. When ReadObject returns, the child reports the bytes it consumed and what it read;
// the parent pushes the bytes it sent beyond those back onto its stream. So the parent's stream ends where MRPT's
// in-process read would have left it, and valid files read as before.
//
// Why fork without exec: the child is this process, with MRPT's class registry exactly as the program has it
// (classes a program or test registers itself included), in every program, test and fuzz target linking this
// library, with no helper executable to install and find. The costs, written down: the child inherits only the
// forking thread, so a lock another thread held at the fork stays held in the child (a child that blocks on one is
// killed at the timeout: an InputError on a valid file; the reader's thread is the only one using MRPT's
// deserialization, so none is known); the parent's pages are shared copy-on-write with the child while it lives; a
// fork per rawlog (about 5 ms in the ASan fuzzer). Why one child per reader and not one per process: a child that
// read a corrupt object without an exception may have a corrupt heap; it must not read another file.
//
// The child: its address space may grow by at most `memory_budget_bytes` beyond what it inherited (RLIMIT_AS, set
// relative to its size at the fork, so a large parent does not leave it without memory; under ASan it bounds large
// blocks only); default signal handlers, no core files, only its socket open; a seccomp filter (libseccomp) lets it
// compute, allocate, use that socket and end, and makes every other system call fail with EPERM (no file, network,
// process or exec: restrictSystemCalls in isolated_object_child.cpp); it leaves by _exit only (an exit()
// inside MRPT included), so no atexit handler or death callback of the parent (libFuzzer's would save the input as a
// finding) runs in it. libFuzzer's malloc hook does run in it: fuzz_rawlog.options keeps single allocations under
// its limit. The parent writes with send(MSG_NOSIGNAL): a dead child is an error, not a SIGPIPE. Children are
// always reaped.
#include <mrpt/system/datetime.h>
#include <sys/types.h>

#include <cstdint>
#include <string>
#include <vector>

#include "rawlog_bytes.h"

namespace quasiloc::dataset::detail
{
/** What MRPT read, or why it could not. */
struct IsolatedObject
{
    std::string error;       ///< empty when the object was read; else MRPT's exception or how the child ended
    bool truncated = false;  ///< with `error`: MRPT asked for bytes beyond the end of the stream
    std::string class_name;  ///< MRPT's name of the object's class
    bool is_observation = false;
    mrpt::Clock::time_point timestamp;  ///< of an observation
};

class IsolatedObjectReader
{
   public:
    struct Options
    {
        int timeout_ms = 10'000;  ///< the child must answer (ask for bytes, or report) within this
        std::uint64_t memory_budget_bytes = 4ULL << 30;
    };

    IsolatedObjectReader() : IsolatedObjectReader(Options{}) {}
    explicit IsolatedObjectReader(const Options& options) : options_(options) {}
    ~IsolatedObjectReader();  // kills and reaps the child
    IsolatedObjectReader(const IsolatedObjectReader&) = delete;
    IsolatedObjectReader& operator=(const IsolatedObjectReader&) = delete;

    /** Reads the next object of `in` (header included) with MRPT's CArchive::ReadObject in the child. On success
     *  `in` is positioned after the object; on failure (`error` set) its position is undefined. Throws
     *  std::runtime_error only when no child can be started (fork or socketpair fails). */
    IsolatedObject read(RawlogStream& in);

    /** Children forked so far (one unless a child died). */
    int childrenStarted() const { return children_started_; }

   private:
    void startChild();
    IsolatedObject serve(RawlogStream& in);
    void answerRequest(RawlogStream& in, std::uint32_t want);
    IsolatedObject finish(RawlogStream& in, const std::string& done);
    static IsolatedObject failure(const std::string& failed);
    std::string stopChild(bool kill_first);

    Options options_;
    pid_t pid_ = -1;
    int fd_ = -1;                           // the parent's end of the socket pair
    std::vector<std::uint8_t> last_chunk_;  // the last bytes sent: the child's unconsumed read-ahead is among them
    std::uint64_t sent_ = 0;                // bytes sent for the current object
    int children_started_ = 0;
};

}  // namespace quasiloc::dataset::detail
