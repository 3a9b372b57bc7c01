// The parent's side of IsolatedObjectReader (isolated_object_reader.h); the child's is isolated_object_child.cpp.
#include "isolated_object_reader.h"

#include <poll.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <thread>

#include "isolated_object_protocol.h"

namespace quasiloc::dataset::detail
{
namespace
{
using namespace isolated;

/** The child cannot go on with this object: it ended, did not answer in time, or broke the protocol. */
struct ChildLost
{
    enum Kind
    {
        Ended,
        TimedOut,
        Garbage
    } kind;
    std::string detail;
};

/** Waits until `fd` is ready for `events`; ChildLost when `timeout_ms` pass first. */
void waitFor(int fd, short events, int timeout_ms)
{
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
    for (;;)
    {
        const auto left =
            std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
        pollfd p{fd, events, 0};
        const int n = ::poll(&p, 1, int(std::max<std::int64_t>(0, left.count())));
        if (n > 0) return;  // ready, or hung up / error: the read or write that follows finds out which
        if (n == 0) throw ChildLost{ChildLost::TimedOut, ""};
        if (errno != EINTR) throw ChildLost{ChildLost::Garbage, std::string("poll: ") + std::strerror(errno)};
    }
}

void sendAll(int fd, const void* data, size_t n, int timeout_ms)
{
    const auto* p = static_cast<const char*>(data);
    while (n > 0)
    {
        waitFor(fd, POLLOUT, timeout_ms);
        // MSG_NOSIGNAL: a child that died is EPIPE here, not a SIGPIPE that ends this process.
        const ssize_t k = ::send(fd, p, n, MSG_NOSIGNAL | MSG_DONTWAIT);
        if (k < 0 && (errno == EINTR || errno == EAGAIN)) continue;
        if (k <= 0) throw ChildLost{ChildLost::Ended, ""};
        p += k;
        n -= size_t(k);
    }
}

void recvAll(int fd, void* data, size_t n, int timeout_ms)
{
    auto* p = static_cast<char*>(data);
    while (n > 0)
    {
        waitFor(fd, POLLIN, timeout_ms);
        const ssize_t k = ::recv(fd, p, n, MSG_DONTWAIT);
        if (k < 0 && (errno == EINTR || errno == EAGAIN)) continue;
        if (k <= 0) throw ChildLost{ChildLost::Ended, ""};  // EOF or ECONNRESET: the child has gone
        p += k;
        n -= size_t(k);
    }
}

template <class T>
T podAt(const std::string& bytes, size_t at)
{
    T value;
    std::memcpy(&value, bytes.data() + at, sizeof value);
    return value;
}

/** "with signal 11 (SIGSEGV)", "with exit status 1". */
std::string describeStatus(int status)
{
    if (WIFSIGNALED(status))
    {
        const int s = WTERMSIG(status);
        const char* abbrev = ::sigabbrev_np(s);
        return "with signal " + std::to_string(s) + (abbrev ? std::string(" (SIG") + abbrev + ")" : "");
    }
    if (WIFEXITED(status)) return "with exit status " + std::to_string(WEXITSTATUS(status));
    return "with wait status " + std::to_string(status);
}

/** Reaps `pid`; returns how it ended. A child whose socket has closed is ending: it gets 2 s, then it is killed. */
std::string reap(pid_t pid, bool kill_first)
{
    int status = 0;
    for (int waited_us = 0; !kill_first && waited_us < 2'000'000; waited_us += 100)
    {
        const pid_t r = ::waitpid(pid, &status, WNOHANG);
        if (r == pid) return describeStatus(status);
        if (r < 0 && errno != EINTR) return "(its status is unknown: " + std::string(std::strerror(errno)) + ")";
        std::this_thread::sleep_for(std::chrono::microseconds(100));
    }
    ::kill(pid, SIGKILL);
    pid_t r;
    while ((r = ::waitpid(pid, &status, 0)) < 0 && errno == EINTR)
    {}
    if (r != pid) return "(its status is unknown: " + std::string(std::strerror(errno)) + ")";
    return describeStatus(status);
}
}  // namespace

IsolatedObjectReader::~IsolatedObjectReader() { stopChild(true); }

IsolatedObject IsolatedObjectReader::read(RawlogStream& in)
{
    // A child that died while idle (killed from outside) is replaced, not blamed on this object.
    if (pid_ >= 0 && ::waitpid(pid_, nullptr, WNOHANG) == pid_)
    {
        pid_ = -1;
        stopChild(false);
    }
    if (pid_ < 0) startChild();
    try
    {
        return serve(in);
    }
    catch (const ChildLost& lost)
    {
        IsolatedObject failed;
        const std::string ended = stopChild(lost.kind != ChildLost::Ended);
        if (lost.kind == ChildLost::Ended)
            failed.error = "the reading process ended " + ended;
        else if (lost.kind == ChildLost::TimedOut)
            failed.error =
                "the reading process did not answer within " + std::to_string(options_.timeout_ms) + " ms (killed)";
        else
            failed.error = "the reading process broke the protocol (" + lost.detail + "; killed)";
        return failed;
    }
}

void IsolatedObjectReader::startChild()
{
    int fds[2];
    if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, fds) != 0)
        throw std::runtime_error(std::string("rawlog reader: socketpair failed: ") + std::strerror(errno));
    std::fflush(nullptr);  // what stdio holds now must not be written by the child too
    const pid_t pid = ::fork();
    if (pid < 0)
    {
        const int e = errno;
        ::close(fds[0]);
        ::close(fds[1]);
        throw std::runtime_error(std::string("rawlog reader: fork failed: ") + std::strerror(e));
    }
    if (pid == 0)
    {
        ::close(fds[0]);
        isolated::runChild(fds[1], options_.memory_budget_bytes);
    }
    ::close(fds[1]);
    pid_ = pid;
    fd_ = fds[0];
    ++children_started_;
}

std::string IsolatedObjectReader::stopChild(bool kill_first)
{
    if (fd_ >= 0) ::close(fd_);  // an idle child ends at the end of its socket
    fd_ = -1;
    if (pid_ < 0) return "";
    const std::string ended = reap(pid_, kill_first);
    pid_ = -1;
    return ended;
}

IsolatedObject IsolatedObjectReader::serve(RawlogStream& in)
{
    sent_ = 0;
    last_chunk_.clear();
    const char command = kReadObject;
    sendAll(fd_, &command, 1, options_.timeout_ms);
    answerRequest(in, kMaxChunk);  // the first bytes with the command
    for (;;)
    {
        char type = 0;
        std::uint32_t length = 0;
        recvAll(fd_, &type, 1, options_.timeout_ms);
        recvAll(fd_, &length, sizeof length, options_.timeout_ms);
        if (length > kMaxPayload)
            throw ChildLost{ChildLost::Garbage, "a message of " + std::to_string(length) + " bytes"};
        std::string payload(length, '\0');
        recvAll(fd_, payload.data(), length, options_.timeout_ms);
        if (type == kRequest && length == sizeof(std::uint32_t))
            answerRequest(in, podAt<std::uint32_t>(payload, 0));
        else if (type == kFailed && length >= kFailedPrefix)
            return failure(payload);
        else if (type == kDone && length > kDonePrefix)
            return finish(in, payload);
        else
            throw ChildLost{ChildLost::Garbage, "message type " + std::to_string(int(type))};
    }
}

void IsolatedObjectReader::answerRequest(RawlogStream& in, std::uint32_t want)
{
    if (want == 0 || want > kMaxChunk)
        throw ChildLost{ChildLost::Garbage, "a request for " + std::to_string(want) + " bytes"};
    last_chunk_.resize(want);
    const auto n = static_cast<std::uint32_t>(in.Read(last_chunk_.data(), want));
    last_chunk_.resize(n);
    sendAll(fd_, &n, sizeof n, options_.timeout_ms);
    sendAll(fd_, last_chunk_.data(), n, options_.timeout_ms);
    sent_ += n;
}

IsolatedObject IsolatedObjectReader::finish(RawlogStream& in, const std::string& done)
{
    // The child asks for bytes only when it has consumed all it had: what it did not consume is in the last chunk.
    const auto consumed = podAt<std::uint64_t>(done, 0);
    if (consumed > sent_ || sent_ - consumed > last_chunk_.size())
        throw ChildLost{ChildLost::Garbage, std::to_string(consumed) + " bytes consumed of " + std::to_string(sent_)};
    const size_t unconsumed = size_t(sent_ - consumed);
    in.pushBack(std::vector<std::uint8_t>(last_chunk_.end() - std::ptrdiff_t(unconsumed), last_chunk_.end()));
    IsolatedObject object;
    object.timestamp = mrpt::Clock::time_point(mrpt::Clock::duration(podAt<std::int64_t>(done, 8)));
    object.is_observation = podAt<std::uint8_t>(done, 16) != 0;
    object.class_name = done.substr(kDonePrefix);
    return object;
}

IsolatedObject IsolatedObjectReader::failure(const std::string& failed)
{
    IsolatedObject object;
    object.error = failed.size() > kFailedPrefix ? failed.substr(kFailedPrefix) : "MRPT gave no reason";
    object.truncated = failed[0] != 0;
    return object;
}

}  // namespace quasiloc::dataset::detail
