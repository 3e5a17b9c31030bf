#include "slamprep/eval/formats/cdr.hpp"

#include <algorithm>
#include <bit>
#include <cstring>

#include "slamprep/core/error.hpp"

namespace slamprep::eval {
namespace {

static_assert(std::endian::native == std::endian::little, "the CDR writer assumes a LE host");

constexpr std::size_t kHeaderSize = 4;

}  // namespace

CdrWriter::CdrWriter() : buffer_({'\0', '\1', '\0', '\0'}) {}

void CdrWriter::align(std::size_t n) {
  const std::size_t offset = buffer_.size() - kHeaderSize;
  buffer_.append((n - offset % n) % n, '\0');
}

void CdrWriter::put(const void* data, std::size_t size, std::size_t alignment) {
  align(alignment);
  buffer_.append(static_cast<const char*>(data), size);
}

void CdrWriter::string(std::string_view s) {
  u32(static_cast<std::uint32_t>(s.size() + 1));
  buffer_.append(s);
  buffer_.push_back('\0');
}

void CdrWriter::sequenceSize(std::size_t n) {
  u32(static_cast<std::uint32_t>(n));
}

CdrReader::CdrReader(std::string_view data, std::string where)
    : data_(data), where_(std::move(where)) {
  if (data_.size() < kHeaderSize)
    throw InputError(where_, "CDR: message shorter than its 4-byte encapsulation header");
  const auto kind = static_cast<unsigned char>(data_[1]);
  if (data_[0] != 0 || kind > 1)
    throw InputError(where_, "CDR: unsupported encapsulation " + std::to_string(int(data_[0])) +
                                 "," + std::to_string(int(kind)) +
                                 " (only plain CDR, big or little endian)");
  swap_ = kind == 0;  // 0 = CDR_BE on a little-endian host
}

void CdrReader::align(std::size_t n) {
  const std::size_t offset = pos_ - kHeaderSize;
  pos_ += (n - offset % n) % n;
}

void CdrReader::get(void* out, std::size_t size, std::string_view field) {
  align(size);
  if (pos_ > data_.size() || data_.size() - pos_ < size)
    throw InputError(where_, std::string(field) + ": message truncated at byte " +
                                 std::to_string(pos_) + " of " + std::to_string(data_.size()));
  std::memcpy(out, data_.data() + pos_, size);
  if (swap_) std::reverse(static_cast<char*>(out), static_cast<char*>(out) + size);
  pos_ += size;
}

std::uint8_t CdrReader::u8(std::string_view field) {
  std::uint8_t v;
  get(&v, 1, field);
  return v;
}
std::int32_t CdrReader::i32(std::string_view field) {
  std::int32_t v;
  get(&v, 4, field);
  return v;
}
std::uint32_t CdrReader::u32(std::string_view field) {
  std::uint32_t v;
  get(&v, 4, field);
  return v;
}
float CdrReader::f32(std::string_view field) {
  float v;
  get(&v, 4, field);
  return v;
}
double CdrReader::f64(std::string_view field) {
  double v;
  get(&v, 8, field);
  return v;
}

std::string CdrReader::string(std::string_view field) {
  const std::uint32_t n = u32(field);
  if (n == 0) return {};  // some writers emit 0 for an empty string
  if (n > data_.size() - pos_)
    throw InputError(where_, std::string(field) + ": string length " + std::to_string(n) +
                                 " exceeds the message");
  std::string s(data_.substr(pos_, n - 1));
  if (data_[pos_ + n - 1] != '\0')
    throw InputError(where_, std::string(field) + ": string not NUL-terminated");
  pos_ += n;
  return s;
}

std::size_t CdrReader::sequenceSize(std::string_view field, std::size_t min_element_size) {
  const std::uint32_t n = u32(field);
  const std::size_t left = data_.size() - pos_;
  if (min_element_size > 0 && n > left / min_element_size)
    throw InputError(where_, std::string(field) + ": sequence of " + std::to_string(n) +
                                 " elements does not fit in the " + std::to_string(left) +
                                 " bytes left");
  return n;
}

}  // namespace slamprep::eval
