#pragma once
// OMG CDR (XCDR1 "plain CDR"), the serialisation ROS 2 uses for every message (rmw "cdr"
// encoding): a 4-byte encapsulation header {0x00, 0x01 (little endian) or 0x00 (big endian),
// 0x00, 0x00}, then the fields in declaration order, each primitive aligned to its own size
// (at most 8) counted from the first byte after the header. Strings: uint32 length including
// the terminating NUL, the bytes, NUL. Sequences: uint32 element count, then the elements. Fixed
// arrays: the elements only.

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace slamprep::eval {

/// Writes little-endian CDR with the CDR_LE encapsulation header.
class CdrWriter {
 public:
  CdrWriter();

  void u8(std::uint8_t v) { put(&v, 1, 1); }
  void i32(std::int32_t v) { put(&v, 4, 4); }
  void u32(std::uint32_t v) { put(&v, 4, 4); }
  void f32(float v) { put(&v, 4, 4); }
  void f64(double v) { put(&v, 8, 8); }
  void string(std::string_view s);
  /// A sequence length (uint32); the caller then writes the elements.
  void sequenceSize(std::size_t n);

  /// The finished message, header included.
  const std::string& bytes() const { return buffer_; }

 private:
  void align(std::size_t n);
  void put(const void* data, std::size_t size, std::size_t alignment);
  std::string buffer_;
};

/// Reads CDR (either byte order, from the encapsulation header). Every read is bounds checked:
/// on truncated or inconsistent data it throws InputError naming `where` and the field.
class CdrReader {
 public:
  /// `where` names the message in errors (e.g. "bag.mcap: /scan message 12 at offset 4242").
  CdrReader(std::string_view data, std::string where);

  std::uint8_t u8(std::string_view field);
  std::int32_t i32(std::string_view field);
  std::uint32_t u32(std::string_view field);
  float f32(std::string_view field);
  double f64(std::string_view field);
  std::string string(std::string_view field);
  /// A sequence length; rejects counts that cannot fit in the remaining bytes at
  /// `min_element_size` bytes each (so a corrupt length never allocates gigabytes).
  std::size_t sequenceSize(std::string_view field, std::size_t min_element_size);

  std::size_t offset() const { return pos_; }
  const std::string& where() const { return where_; }

 private:
  void align(std::size_t n);
  void get(void* out, std::size_t size, std::string_view field);
  std::string_view data_;
  std::string where_;
  std::size_t pos_ = 4;
  bool swap_ = false;
};

}  // namespace slamprep::eval
