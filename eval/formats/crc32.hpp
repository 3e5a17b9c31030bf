#pragma once
// CRC-32 (IEEE 802.3), the checksum MCAP puts on its data section, summary and chunks.

#include <cstdint>
#include <string_view>

namespace slamprep::eval {

/// CRC-32 (IEEE 802.3, reflected polynomial 0xEDB88320), as zlib computes it; `crc` continues a
/// previous value.
std::uint32_t crc32(std::string_view bytes, std::uint32_t crc = 0);

}  // namespace slamprep::eval
