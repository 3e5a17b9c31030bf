#include "slamprep/core/input_file.hpp"

#include <fstream>

#include "slamprep/core/error.hpp"

namespace slamprep {
namespace {

namespace fs = std::filesystem;

std::string kindOf(fs::file_type type) {
  switch (type) {
    case fs::file_type::directory:
      return "a directory";
    case fs::file_type::character:
      return "a character device";
    case fs::file_type::block:
      return "a block device";
    case fs::file_type::fifo:
      return "a FIFO (pipe)";
    case fs::file_type::socket:
      return "a socket";
    default:
      return "not a regular file";
  }
}

std::string sizeText(std::uintmax_t bytes) {
  if (bytes >= (1u << 20) && bytes % (1u << 20) == 0) return std::to_string(bytes >> 20) + " MiB";
  if (bytes >= 1024 && bytes % 1024 == 0) return std::to_string(bytes >> 10) + " KiB";
  return std::to_string(bytes) + " bytes";
}

}  // namespace

void checkInputFileSize(const fs::path& file, std::string_view what, std::uintmax_t max_bytes) {
  std::error_code ec;
  const fs::file_status status = fs::status(file, ec);
  if (!fs::exists(status)) throw InputError(file.string(), "cannot open " + std::string(what));
  if (!fs::is_regular_file(status))
    throw InputError(file.string(), "cannot read " + std::string(what) + ": " +
                                        kindOf(status.type()) + ", not a regular file");
  const std::uintmax_t size = fs::file_size(file, ec);
  if (ec) throw InputError(file.string(), "cannot read " + std::string(what));
  if (size > max_bytes)
    throw InputError(file.string(), std::string(what) + " of " + std::to_string(size) +
                                        " bytes is larger than the limit of " +
                                        sizeText(max_bytes));
}

std::string readInputFile(const fs::path& file, std::string_view what, std::uintmax_t max_bytes) {
  checkInputFileSize(file, what, max_bytes);
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file.string(), "cannot open " + std::string(what));
  std::string text;
  char chunk[65536];
  while (in.read(chunk, sizeof chunk) || in.gcount() > 0) {
    text.append(chunk, static_cast<std::size_t>(in.gcount()));
    if (text.size() > max_bytes)  // it grew while being read
      throw InputError(file.string(),
                       std::string(what) + " is larger than the limit of " + sizeText(max_bytes));
  }
  if (in.bad()) throw InputError(file.string(), "cannot read " + std::string(what));
  return text;
}

}  // namespace slamprep
