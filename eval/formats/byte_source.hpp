#pragma once
// Where the MCAP reader pulls its bytes from: a file read piece by piece (so a bag is never held
// whole in memory), or bytes already in memory (tests, fuzzing).

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>

namespace slamprep::eval {

class ByteSource {
 public:
  virtual ~ByteSource() = default;
  /// What errors call the source (the file's path).
  virtual const std::string& name() const = 0;
  virtual std::uint64_t size() const = 0;
  /// Replaces `out` with the `n` bytes at `offset`; the caller keeps inside size(). Throws
  /// InputError naming the source when the bytes cannot be read.
  virtual void read(std::uint64_t offset, std::size_t n, std::string& out) = 0;
};

/// A file read through a 1 MiB read-ahead buffer. Throws InputError when it cannot be opened or
/// is not a regular file. Errors name `name` when given (an unpacked copy names its original).
std::unique_ptr<ByteSource> openFileSource(const std::filesystem::path& file,
                                           const std::string& name = "");

/// Bytes in memory, not copied: `bytes` must outlive the source.
std::unique_ptr<ByteSource> memorySource(std::string_view bytes, std::string name);

}  // namespace slamprep::eval
