#pragma once
// Chunk compression of MCAP files: "zstd" and "lz4" (the LZ4 frame format), the two compressions
// the MCAP specification names, through the system libraries libzstd and liblz4 (linked); and
// rosbag2's own compression (zstd per message or per file).

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

#include "slamprep/core/enum_names.hpp"

namespace slamprep::eval {

enum class Compression { kNone, kZstd, kLz4 };
/// As --compression spells them.
inline constexpr auto kCompressionNames = std::to_array<EnumName<Compression>>({
    {Compression::kNone, "none"},
    {Compression::kZstd, "zstd"},
    {Compression::kLz4, "lz4"},
});

/// A name of kCompressionNames; throws InputError naming `where` otherwise.
Compression parseCompression(const std::string& name, const std::string& where = "--compression");
/// The name MCAP records carry: "" (none), "zstd" or "lz4".
std::string_view mcapCompressionName(Compression c);

/// Largest chunk this reader unpacks: 1 GiB, and at most 4096 times the compressed size plus
/// 1 MiB (so a corrupt size field cannot make it allocate gigabytes).
bool plausibleUncompressedSize(std::uint64_t compressed_size, std::uint64_t uncompressed_size);

/// Unpacks `data` (zstd frames, or one LZ4 frame) into exactly `uncompressed_size` bytes.
/// Throws InputError(where, ...) for an unknown compression, corrupt data or a size that does
/// not match.
std::string decompressChunk(std::string_view compression, std::string_view data,
                            std::uint64_t uncompressed_size, const std::string& where);

/// `data` as one zstd frame (level 3, zstd's default) or one LZ4 frame (default preferences);
/// kNone returns it unchanged.
std::string compressChunk(Compression c, std::string_view data);

/// One zstd-compressed message of a rosbag2 bag recorded with compression_mode MESSAGE: frames
/// whose content size is unknown are unpacked as a stream. Throws InputError(where, ...) on
/// corrupt data or more than `max_size` bytes out (a corrupt frame cannot allocate gigabytes).
std::string decompressZstd(std::string_view data, const std::string& where,
                           std::uint64_t max_size = std::uint64_t{1} << 30);

/// A whole zstd-compressed file (rosbag2 compression_mode FILE) unpacked into `to`, streamed
/// (1 MiB buffers, never the file in memory). Throws InputError naming `from` on corrupt or
/// truncated data, or `to` when it cannot be written.
void decompressZstdFile(const std::filesystem::path& from, const std::filesystem::path& to);

}  // namespace slamprep::eval
