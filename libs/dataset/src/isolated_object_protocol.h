#pragma once
// The messages between IsolatedObjectReader (isolated_object_reader.h) and its child, over a Unix socket pair.
//
//   parent -> child: kReadObject (1 byte): read one object; the first bytes follow at once, as a reply to a
//                    kRequest of kMaxChunk (most objects then need one round trip).
//                    a reply to kRequest: uint32 n, then n bytes (fewer than asked: the stream has ended).
//   child -> parent: a type byte, uint32 payload length, the payload:
//                    kRequest  uint32 how many bytes (1 to kMaxChunk);
//                    kDone     uint64 bytes consumed, int64 timestamp (MRPT ticks), uint8 is an observation,
//                              the class name;
//                    kFailed   uint8 MRPT asked for bytes beyond the end of the stream, the reason (MRPT's
//                              exception text).
#include <cstddef>
#include <cstdint>

namespace quasiloc::dataset::detail::isolated
{
constexpr std::uint32_t kMaxChunk = 64 * 1024;    ///< bytes per request: an image is not thousands of round trips
constexpr std::uint32_t kMaxPayload = 64 * 1024;  ///< a longer message is garbage
constexpr std::size_t kDonePrefix = 8 + 8 + 1;    ///< kDone's fields before the class name
constexpr std::size_t kFailedPrefix = 1;          ///< kFailed's field before the reason

enum Message : char
{
    kReadObject = 'O',
    kRequest = 'R',
    kDone = 'D',
    kFailed = 'E',
};

/** The child's side: reads objects on request until the parent closes `socket_fd`, then _exit(0). Never returns. */
[[noreturn]] void runChild(int socket_fd, std::uint64_t memory_budget_bytes);

}  // namespace quasiloc::dataset::detail::isolated
