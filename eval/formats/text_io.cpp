#include "slamprep/eval/formats/text_io.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>

#include "slamprep/core/error.hpp"

namespace slamprep::eval {
namespace {

bool isBlank(char c) {
  return c == ' ' || c == '\t' || c == '\r';
}

// A field shown in an error message: quoted, and cut short if it is long.
std::string quoted(std::string_view text) {
  constexpr std::size_t kMax = 40;
  std::string out = "\"";
  out += text.substr(0, kMax);
  if (text.size() > kMax) out += "...";
  return out + "\"";
}

[[noreturn]] void fieldError(const TextLocation& where, std::string_view field,
                             const std::string& what) {
  throw InputError(where.str(), std::string(field) + ": " + what);
}

}  // namespace

void appendDouble(std::string& out, double value) {
  if (value == 0.0 && std::signbit(value)) {
    out += "-0.0";
    return;
  }
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  out.append(buffer, result.ptr);
}

void appendInt(std::string& out, std::int64_t value) {
  char buffer[24];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  out.append(buffer, result.ptr);
}

std::string TextLocation::str() const {
  return line == 0 ? file : file + ":" + std::to_string(line);
}

double parseFiniteDouble(std::string_view text, const TextLocation& where, std::string_view field) {
  if (text.empty()) fieldError(where, field, "empty, expected a number");
  double value = 0.0;
  const char* end = text.data() + text.size();
  const auto result = std::from_chars(text.data(), end, value);
  if (result.ec == std::errc::result_out_of_range)
    fieldError(where, field, "number out of range: " + quoted(text));
  if (result.ec != std::errc() || result.ptr != end)
    fieldError(where, field, "not a number: " + quoted(text));
  if (!std::isfinite(value)) fieldError(where, field, "must be finite, got " + quoted(text));
  return value;
}

std::int64_t parseInt64(std::string_view text, const TextLocation& where, std::string_view field) {
  if (text.empty()) fieldError(where, field, "empty, expected an integer");
  std::int64_t value = 0;
  const char* end = text.data() + text.size();
  const auto result = std::from_chars(text.data(), end, value);
  if (result.ec == std::errc::result_out_of_range)
    fieldError(where, field, "integer out of range: " + quoted(text));
  if (result.ec != std::errc() || result.ptr != end)
    fieldError(where, field, "not an integer: " + quoted(text));
  return value;
}

void requireIncreasing(double previous_s, double stamp_s, const TextLocation& where,
                       std::string_view field) {
  if (stamp_s > previous_s) return;
  std::string what = stamp_s == previous_s ? "duplicate timestamp " : "timestamp ";
  appendDouble(what, stamp_s);
  what += " after ";
  appendDouble(what, previous_s);
  fieldError(where, field, what + " (timestamps must increase strictly)");
}

std::string_view trim(std::string_view text) {
  while (!text.empty() && isBlank(text.front())) text.remove_prefix(1);
  while (!text.empty() && isBlank(text.back())) text.remove_suffix(1);
  return text;
}

void splitFields(std::string_view line, char separator, std::vector<std::string_view>& fields) {
  fields.clear();
  while (true) {
    const std::size_t cut = line.find(separator);
    fields.push_back(trim(line.substr(0, cut)));
    if (cut == std::string_view::npos) return;
    line.remove_prefix(cut + 1);
  }
}

void splitWhitespace(std::string_view line, std::vector<std::string_view>& fields) {
  fields.clear();
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && isBlank(line[i])) ++i;
    const std::size_t start = i;
    while (i < line.size() && !isBlank(line[i])) ++i;
    if (i > start) fields.push_back(line.substr(start, i - start));
  }
}

bool LineCursor::next(std::string_view& line) {
  if (pos_ >= text_.size()) return false;
  const std::size_t end = text_.find('\n', pos_);
  const std::size_t stop = end == std::string_view::npos ? text_.size() : end;
  line = text_.substr(pos_, stop - pos_);
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  pos_ = stop + 1;
  ++line_;
  return true;
}

std::string readTextFile(const std::filesystem::path& path) {
  std::error_code ec;
  if (std::filesystem::exists(path, ec) && !std::filesystem::is_regular_file(path, ec))
    throw InputError(path.string(), "not a regular file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string(), "cannot open file (missing or unreadable)");
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  if (size < 0) throw InputError(path.string(), "cannot read file (not a regular file?)");
  std::string text(static_cast<std::size_t>(size), '\0');
  in.seekg(0, std::ios::beg);
  in.read(text.data(), size);
  if (!in) throw InputError(path.string(), "read failed");
  return text;
}

void writeTextFile(const std::filesystem::path& path, std::string_view text) {
  bool done = false;
  writeTextFile(path, [&](std::string& out) {
    if (done) return false;
    out.assign(text);
    return done = true;
  });
}

void writeTextFile(const std::filesystem::path& path,
                   const std::function<bool(std::string&)>& next_piece) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0)
    throw InputError(path.string(), std::string("cannot create: ") + std::strerror(errno));
  std::string piece;
  try {
    while ((piece.clear(), next_piece(piece))) {
      std::size_t done = 0;
      while (done < piece.size()) {
        const ssize_t n = ::write(fd, piece.data() + done, piece.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0)
          throw InputError(path.string(), std::string("write failed: ") + std::strerror(errno));
        done += static_cast<std::size_t>(n);
      }
    }
  } catch (...) {
    ::close(fd);
    throw;
  }
  // Durable before the directory rename publishes it (writeDataset's atomicity).
  const bool synced = ::fsync(fd) == 0;
  const bool closed = ::close(fd) == 0;
  if (!synced || !closed)
    throw InputError(path.string(), std::string("flush failed: ") + std::strerror(errno));
}

void writeRows(const std::filesystem::path& path, std::string_view header, std::size_t rows,
               const std::function<void(std::string&, std::size_t)>& append_row) {
  std::size_t k = 0;
  bool header_written = false;
  writeTextFile(path, [&](std::string& out) {
    if (!header_written) out += header;
    header_written = true;
    for (const std::size_t end = std::min(rows, k + 4096); k < end; ++k) append_row(out, k);
    return !out.empty();
  });
}

}  // namespace slamprep::eval
