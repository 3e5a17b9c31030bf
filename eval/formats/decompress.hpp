#pragma once
// Decompression of MCAP chunks ("zstd" and "lz4", the two compressions the MCAP specification
// names). Debian ships no -dev package of either on this project's machines, but every Debian
// system has the runtime libraries (dpkg and apt depend on them): they are loaded with dlopen
// at first use, so nothing changes in the build.

#include <cstdint>
#include <string>
#include <string_view>

namespace slamprep::eval {

/// Largest chunk this reader unpacks: 1 GiB, and at most 4096 times the compressed size plus
/// 1 MiB (so a corrupt size field cannot make it allocate gigabytes).
bool plausibleUncompressedSize(std::uint64_t compressed_size, std::uint64_t uncompressed_size);

/// Unpacks `data` (one zstd frame, or one LZ4 frame) into exactly `uncompressed_size` bytes.
/// Throws InputError(where, ...) for an unknown compression, a missing system library, corrupt
/// data or a size that does not match.
std::string decompressChunk(std::string_view compression, std::string_view data,
                            std::uint64_t uncompressed_size, const std::string& where);

}  // namespace slamprep::eval
