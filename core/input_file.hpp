#pragma once
// Reading an input file whole, refused up front when it cannot be a real input: a device, FIFO or
// folder (/dev/zero never ends), or more bytes than any such file holds (docs/design.md, "Input
// limits").

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace slamprep {

/// Size limits of the input files read whole (a dataset's logs are larger and read by their own
/// readers). YAML: worlds, scenarios, suites, bag metadata. yaml-cpp takes up to 1.3 s and 160 MB
/// for 1 MiB of small nodes, so 512 KiB (200 times the largest world here; 10 000 walls fit)
/// keeps a refusal of the file's contents within a second and 200 MB.
inline constexpr std::uintmax_t kMaxYamlFileBytes = 512u << 10;
inline constexpr std::uintmax_t kMaxConfigFileBytes = 16u << 20;  ///< JSON settings: 16 MiB
inline constexpr std::uintmax_t kMaxRecordFileBytes = 1u << 30;   ///< record lists: 1 GiB

/// Throws InputError(file, ...) unless `file` is a regular file (after symlinks) of at most
/// `max_bytes`; `what` names the kind of file in the message ("world file").
void checkInputFileSize(const std::filesystem::path& file, std::string_view what,
                        std::uintmax_t max_bytes);

/// checkInputFileSize, then the whole file; a file that grew past `max_bytes` while being read is
/// refused as well.
std::string readInputFile(const std::filesystem::path& file, std::string_view what,
                          std::uintmax_t max_bytes);

}  // namespace slamprep
