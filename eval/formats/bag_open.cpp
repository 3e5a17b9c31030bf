#include "slamprep/eval/formats/bag_open.hpp"

#include <unistd.h>

#include <atomic>

#include "slamprep/core/error.hpp"
#include "slamprep/eval/formats/compression.hpp"

namespace slamprep::eval {
namespace fs = std::filesystem;
namespace {

std::uintmax_t sizeOr0(const fs::path& file) {
  std::error_code ec;
  const std::uintmax_t n = fs::file_size(file, ec);
  return ec ? 0 : n;
}

std::string megabytes(std::uintmax_t bytes) {
  return std::to_string((bytes + 500000) / 1000000) + " MB";
}

}  // namespace

fs::path OpenBag::scratch(const fs::path& parent) {
  if (!scratch_.empty()) return scratch_;
  static std::atomic<unsigned> counter{0};
  const fs::path base = parent.empty() ? fs::temp_directory_path() : parent;
  const std::string stem = ".slamprep-bag-" + std::to_string(::getpid()) + "-";
  std::error_code ec;
  fs::path dir;
  do {
    dir = base / (stem + std::to_string(counter++));
  } while (!fs::create_directory(dir, ec) && !ec);
  if (ec) throw InputError(dir.string(), "cannot create a scratch folder: " + ec.message());
  scratch_ = dir;
  return scratch_;
}

/// A FILE-compressed storage file unpacked into the scratch folder, named without ".zstd".
fs::path OpenBag::unpacked(const fs::path& file, const fs::path& parent) {
  fs::path name = file.filename();
  if (name.extension() == ".zstd") name.replace_extension();
  const fs::path to = scratch(parent) / name;
  decompressZstdFile(file, to);
  return to;
}

OpenBag::OpenBag(Rosbag2Bag bag, const fs::path& scratch_parent) : bag_(std::move(bag)) {
  try {
    std::uintmax_t unpacked_bytes = 0, recovered = 0;
    for (const fs::path& file : bag_.files) {
      fs::path read = file;
      std::string name = file.string();
      if (bag_.compression == BagCompressionMode::kFile) {
        read = unpacked(file, scratch_parent);
        unpacked_bytes += sizeOr0(read);
        name += " (unpacked)";
      }
      bool immutable = true;
      const fs::path wal = file.string() + "-wal";
      if (bag_.storage == BagStorageKind::kSqlite3 && sizeOr0(wal) > 0) {
        // immutable=1 would ignore the WAL's pages: recover them in a private copy instead.
        const fs::path copy = scratch(scratch_parent) / (read.filename().string() + ".copy");
        fs::copy_file(read, copy, fs::copy_options::overwrite_existing);
        fs::copy_file(wal, copy.string() + "-wal", fs::copy_options::overwrite_existing);
        if (read != file) fs::remove(read);
        read = copy;
        immutable = false;
        ++recovered;
      }
      if (bag_.storage == BagStorageKind::kSqlite3) {
        storages_.push_back(openSqliteStorage(read, immutable, name));
      } else {
        sources_.push_back(openFileSource(read, name));
        storages_.push_back(openMcapStorage(*sources_.back()));
      }
      names_.push_back(name);
    }
    if (unpacked_bytes)
      notes_.push_back(std::to_string(bag_.files.size()) +
                       " storage files compressed whole (compression_mode FILE, zstd) unpacked "
                       "into a scratch folder (" +
                       megabytes(unpacked_bytes) + "), removed after the import");
    if (recovered)
      notes_.push_back(std::to_string(recovered) +
                       " .db3 files have a non-empty -wal beside them (the recording was not "
                       "closed): read from a private copy with their WAL applied");
  } catch (const fs::filesystem_error& e) {
    close();
    throw InputError(e.path1().string(), e.code().message());
  } catch (...) {
    close();  // no destructor runs for a constructor that throws
    throw;
  }
}

void OpenBag::close() {
  storages_.clear();
  sources_.clear();
  std::error_code ignored;
  if (!scratch_.empty()) fs::remove_all(scratch_, ignored);
  scratch_.clear();
}

OpenBag::~OpenBag() {
  close();
}

std::vector<BagStorage*> OpenBag::storages() const {
  std::vector<BagStorage*> out;
  for (const auto& s : storages_) out.push_back(s.get());
  return out;
}

}  // namespace slamprep::eval
