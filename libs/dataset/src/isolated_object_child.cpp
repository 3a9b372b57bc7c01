// The child process of IsolatedObjectReader (isolated_object_reader.h): MRPT reads objects from bytes it asks the
// parent for, and the child reports what it read. Everything here runs in the forked child only.
#include <fcntl.h>
#include <mrpt/io/CStream.h>
#include <seccomp.h>
#include <sys/mman.h>
#include <mrpt/obs/CObservation.h>
#include <mrpt/serialization/CArchive.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <new>
#include <stdexcept>
#include <string>
#include <vector>

#include "isolated_object_protocol.h"

#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define QUASILOC_SANITIZED 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__)
#define QUASILOC_SANITIZED 1
#endif
#ifdef QUASILOC_SANITIZED
#include <sanitizer/common_interface_defs.h>
#endif

namespace quasiloc::dataset::detail::isolated
{
namespace
{
constexpr int kSocket = 3;  // the child's end of the socket pair, moved here

/** The parent has gone or broke the protocol: nobody waits for this child any more. */
[[noreturn]] void parentGone() { _exit(0); }

void sendAll(const void* data, size_t n)
{
    const auto* p = static_cast<const char*>(data);
    while (n > 0)
    {
        const ssize_t k = ::send(kSocket, p, n, MSG_NOSIGNAL);
        if (k < 0 && errno == EINTR) continue;
        if (k <= 0) parentGone();
        p += k;
        n -= size_t(k);
    }
}

void recvAll(void* data, size_t n)
{
    auto* p = static_cast<char*>(data);
    while (n > 0)
    {
        const ssize_t k = ::recv(kSocket, p, n, 0);
        if (k < 0 && errno == EINTR) continue;
        if (k <= 0) parentGone();
        p += k;
        n -= size_t(k);
    }
}

void sendMessage(Message type, const std::string& payload)
{
    const auto length = static_cast<std::uint32_t>(std::min<size_t>(payload.size(), kMaxPayload));
    std::string message(1, char(type));
    message.append(reinterpret_cast<const char*>(&length), sizeof length);
    message.append(payload, 0, length);
    sendAll(message.data(), message.size());
}

template <class T>
void appendPod(std::string& out, const T& value)
{
    out.append(reinterpret_cast<const char*>(&value), sizeof value);
}

/** The object's bytes as MRPT reads them, asked from the parent kMaxChunk at a time. */
class ParentStream : public mrpt::io::CStream
{
   public:
    ParentStream() { receiveChunk(); }  // the first bytes come with the command

    size_t Read(void* buffer, size_t count) override
    {
        auto* out = static_cast<std::uint8_t*>(buffer);
        size_t done = 0;
        while (done < count && (at_ < chunk_.size() || refill()))
        {
            const size_t n = std::min(count - done, chunk_.size() - at_);
            std::memcpy(out + done, chunk_.data() + at_, n);
            at_ += n;
            done += n;
        }
        // All or nothing: MRPT's ReadBuffer accepts a short read and goes on with the rest of the variable
        // uninitialised (a length field cut by the end of the file would say anything); for nothing it throws.
        if (done < count)
        {
            ran_out_ = true;
            return 0;
        }
        consumed_ += done;
        return done;
    }
    bool ranOut() const { return ran_out_; }
    size_t Write(const void*, size_t) override { throw std::logic_error("the rawlog stream is read-only"); }
    uint64_t Seek(int64_t, CStream::TSeekOrigin) override { throw std::logic_error("the rawlog stream cannot seek"); }
    uint64_t getTotalBytesCount() const override { return 0; }
    uint64_t getPosition() const override { return consumed_; }

   private:
    bool refill()
    {
        if (ended_) return false;
        std::string want;
        appendPod(want, kMaxChunk);
        sendMessage(kRequest, want);
        receiveChunk();
        return !chunk_.empty();
    }

    void receiveChunk()
    {
        std::uint32_t n = 0;
        recvAll(&n, sizeof n);
        if (n > kMaxChunk) parentGone();
        chunk_.resize(n);
        recvAll(chunk_.data(), n);
        at_ = 0;
        ended_ = n < kMaxChunk;  // a short answer: the parent's stream has ended
    }

    std::vector<std::uint8_t> chunk_;
    size_t at_ = 0;
    std::uint64_t consumed_ = 0;
    bool ended_ = false;
    bool ran_out_ = false;
};

/** One object: read by MRPT, reported to the parent. The object is destroyed before the report, so that a
 *  destructor that crashes is blamed on this object, not on the next one. */
void readOneObject(std::uint64_t memory_budget_bytes)
{
    ParentStream in;
    std::string done, failure;
    try
    {
        auto object = mrpt::serialization::archiveFrom(in).ReadObject();
        if (!object) throw std::runtime_error("the class cannot be instantiated (abstract or not serializable)");
        const auto obs = std::dynamic_pointer_cast<mrpt::obs::CObservation>(object);
        appendPod(done, std::uint64_t(in.getPosition()));
        appendPod(done, std::int64_t(obs ? obs->timestamp.time_since_epoch().count() : 0));
        appendPod(done, std::uint8_t(obs ? 1 : 0));
        done += object->GetRuntimeClass()->className;
    }
    catch (const std::bad_alloc&)
    {
        failure = "it needs more memory than the " + std::to_string(memory_budget_bytes >> 20) +
                  " MiB the reading process may add (a length field of the file, corrupt?)";
    }
    catch (const std::exception& e)
    {
        failure = e.what();
    }
    catch (...)
    {
        failure = "an exception that is not a std::exception";
    }
    if (failure.empty()) return sendMessage(kDone, done);
    sendMessage(kFailed, std::string(1, in.ranOut() ? '\1' : '\0') + failure);
}

/** exit() inside MRPT (libjpeg's error handler, ...): registered last, so it runs first and ends the child before
 *  the parent's atexit handlers (static destructors, libFuzzer's exit hook, LeakSanitizer) run in it. */
void exitImmediately(int status, void*) { _exit(status); }

/** RLIMIT_AS: what the child has now (inherited) plus the budget, within the hard limit. */
void limitAddressSpace(std::uint64_t budget_bytes)
{
    const int fd = ::open("/proc/self/statm", O_RDONLY | O_CLOEXEC);
    if (fd < 0) return;  // no /proc: unbounded (the timeout still applies)
    char text[64] = {};
    const ssize_t n = ::read(fd, text, sizeof text - 1);
    ::close(fd);
    if (n <= 0) return;
    const std::uint64_t pages = std::strtoull(text, nullptr, 10);  // first field: the address space, in pages
    const std::uint64_t wanted = pages * std::uint64_t(::sysconf(_SC_PAGESIZE)) + budget_bytes;
    rlimit limit{};
    if (::getrlimit(RLIMIT_AS, &limit) != 0) return;
    if (limit.rlim_max == RLIM_INFINITY || wanted < limit.rlim_max) limit.rlim_cur = wanted;
    ::setrlimit(RLIMIT_AS, &limit);
}

#ifdef QUASILOC_SANITIZED
/** A sanitizer report inside MRPT (an allocation over ASan's max_allocation_size_mb, a memory error that its
 *  interceptors caught) ends the child with a reason for the parent; libFuzzer's death callback, inherited, would
 *  have saved the input as a finding of the parent's. */
void sanitizerDied()
{
    static const char kReason[] = "AddressSanitizer stopped it (an allocation over its limit, or a memory error)";
    char message[1 + 4 + kFailedPrefix + sizeof kReason - 1] = {kFailed};
    const std::uint32_t length = kFailedPrefix + sizeof kReason - 1;
    std::memcpy(message + 1, &length, sizeof length);
    std::memcpy(message + 1 + 4 + kFailedPrefix, kReason, sizeof kReason - 1);
    (void)::send(kSocket, message, sizeof message, MSG_NOSIGNAL);
    _exit(99);
}
#endif

#ifndef QUASILOC_SANITIZED
/** What MRPT's readers may still do in the child: compute, allocate (no executable memory), talk on the socket it
 *  inherited, end. Every other system call (open, exec, socket, connect, fork, unlink, ...) fails with EPERM: a reader
 *  that a crafted file turned against the system can neither reach files nor the network. EPERM rather than death, so
 * that an unexpected call on a valid file costs that call, not the read. Without seccomp in the kernel the child goes
 * on unfiltered. */
void restrictSystemCalls()
{
    scmp_filter_ctx filter = seccomp_init(SCMP_ACT_ERRNO(EPERM));
    if (!filter) return;
    const int allowed[] = {
        // the socket (fd 3; stderr for sanitizer reports)
        SCMP_SYS(read), SCMP_SYS(write), SCMP_SYS(readv), SCMP_SYS(writev), SCMP_SYS(recvfrom), SCMP_SYS(sendto),
        SCMP_SYS(recvmsg), SCMP_SYS(sendmsg), SCMP_SYS(close), SCMP_SYS(fstat), SCMP_SYS(newfstatat), SCMP_SYS(lseek),
        // memory
        SCMP_SYS(brk), SCMP_SYS(munmap), SCMP_SYS(mremap), SCMP_SYS(madvise),
        // threads of MRPT or OpenCV, time, waiting
        SCMP_SYS(futex), SCMP_SYS(sched_yield), SCMP_SYS(clock_gettime), SCMP_SYS(gettimeofday),
        SCMP_SYS(clock_nanosleep), SCMP_SYS(nanosleep), SCMP_SYS(pause), SCMP_SYS(ppoll), SCMP_SYS(poll),
        SCMP_SYS(getrandom),
        // ending: _exit, abort() and crashes (which raise their signal with tgkill)
        SCMP_SYS(exit), SCMP_SYS(exit_group), SCMP_SYS(rt_sigreturn), SCMP_SYS(rt_sigprocmask), SCMP_SYS(rt_sigaction),
        SCMP_SYS(sigaltstack), SCMP_SYS(getpid), SCMP_SYS(gettid), SCMP_SYS(tgkill)};
    bool ok = true;
    for (const int call : allowed) ok = ok && seccomp_rule_add(filter, SCMP_ACT_ALLOW, call, 0) == 0;
    // Memory may be mapped and re-protected, but never executable: code that a crafted file smuggled into the
    // child's memory cannot be run (the child needs no new code: it is a fork of a process that has all of it).
    for (const int call : {SCMP_SYS(mmap), SCMP_SYS(mprotect)})
        ok = ok && seccomp_rule_add(filter, SCMP_ACT_ALLOW, call, 1, SCMP_A2(SCMP_CMP_MASKED_EQ, PROT_EXEC, 0)) == 0;
    if (ok) (void)seccomp_load(filter);
    seccomp_release(filter);
}
#endif

void prepareChild(int socket_fd, std::uint64_t memory_budget_bytes)
{
    // Only the socket stays open: the child must not keep the parent's files, or other children's sockets, open.
    if (socket_fd != kSocket && ::dup2(socket_fd, kSocket) < 0) _exit(0);
    ::close_range(kSocket + 1, ~0U, 0);
    // Default signal handlers (a crash ends the child with its signal, not in a handler of the parent's, e.g.
    // libFuzzer's, which would save the input as a finding), nothing blocked, no core files.
    for (int s = 1; s < NSIG; ++s)
        if (s != SIGKILL && s != SIGSTOP) std::signal(s, SIG_DFL);
    sigset_t none;
    sigemptyset(&none);
    ::sigprocmask(SIG_SETMASK, &none, nullptr);
    rlimit core{};
    if (::getrlimit(RLIMIT_CORE, &core) == 0)
    {
        core.rlim_cur = 0;
        ::setrlimit(RLIMIT_CORE, &core);
    }
    limitAddressSpace(memory_budget_bytes);
    ::on_exit(exitImmediately, nullptr);
#ifdef QUASILOC_SANITIZED
    // Sanitizer reports inside MRPT are not findings of the parent's: silence them, end the child.
    __sanitizer_set_death_callback(sanitizerDied);
    const int null = ::open("/dev/null", O_WRONLY);
    if (null >= 0) ::dup2(null, STDERR_FILENO);
    if (null > STDERR_FILENO) ::close(null);
#endif
#ifndef QUASILOC_SANITIZED
    // Last: the set-up above opens /proc/self/statm and /dev/null. Not under ASan (the fuzz build): its runtime
    // needs calls the filter refuses (it ended every child at the first allocation), and the fuzzer would then never
    // reach MRPT's readers in the child.
    restrictSystemCalls();
#endif
}
}  // namespace

void runChild(int socket_fd, std::uint64_t memory_budget_bytes)
{
    prepareChild(socket_fd, memory_budget_bytes);
    for (;;)
    {
        char command = 0;
        recvAll(&command, 1);  // the parent closed the socket: parentGone()
        if (command != kReadObject) parentGone();
        readOneObject(memory_budget_bytes);
    }
}

}  // namespace quasiloc::dataset::detail::isolated
