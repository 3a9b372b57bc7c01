#pragma once
// Byte-level helpers of the ROS 2 bag formats: CRC-32 (zlib's, the ISO-HDLC polynomial MCAP specifies), zstd
// (libzstd) and LZ4 frames (liblz4). Decompression never trusts a declared size for an allocation beyond what the
// data really expands to, and stops at `max_bytes`: a corrupt or hostile file ends in an InputError naming `where`.
#include <cstdint>
#include <string>
#include <vector>

namespace quasiloc::ros
{
std::uint32_t crc32Of(const std::uint8_t* data, std::size_t size, std::uint32_t crc = 0);

/** Every frame of `data` decompressed; more than max_bytes of output is an error. */
std::vector<std::uint8_t> zstdDecompress(const std::uint8_t* data, std::size_t size, std::size_t max_bytes,
                                         const std::string& where);
/** An LZ4 frame (lz4frame.h format, not a raw block) decompressed; more than max_bytes is an error. */
std::vector<std::uint8_t> lz4Decompress(const std::uint8_t* data, std::size_t size, std::size_t max_bytes,
                                        const std::string& where);

std::vector<std::uint8_t> zstdCompress(const std::uint8_t* data, std::size_t size, int level);
std::vector<std::uint8_t> lz4Compress(const std::uint8_t* data, std::size_t size);

/** A zstd-compressed file (rosbag2's file compression: one .db3 or .mcap per file) decompressed to `to`,
 *  streamed. */
void zstdDecompressFile(const std::string& from, const std::string& to);

}  // namespace quasiloc::ros
