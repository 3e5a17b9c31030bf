#include "slamprep/eval/formats/byte_source.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "slamprep/core/error.hpp"

namespace slamprep::eval {
namespace {

class FileSource final : public ByteSource {
 public:
  FileSource(const std::filesystem::path& file, const std::string& name)
      : name_(name.empty() ? file.string() : name) {
    fd_ = ::open(file.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd_ < 0) throw InputError(name_, std::string("cannot open: ") + std::strerror(errno));
    struct stat st {};
    if (::fstat(fd_, &st) != 0 || !S_ISREG(st.st_mode)) {
      ::close(fd_);
      throw InputError(name_, "not a regular file");
    }
    size_ = static_cast<std::uint64_t>(st.st_size);
  }
  ~FileSource() override { ::close(fd_); }
  FileSource(const FileSource&) = delete;
  FileSource& operator=(const FileSource&) = delete;

  const std::string& name() const override { return name_; }
  std::uint64_t size() const override { return size_; }

  void read(std::uint64_t offset, std::size_t n, std::string& out) override {
    if (offset >= buffer_at_ && offset + n <= buffer_at_ + buffer_.size()) {
      out.assign(buffer_, offset - buffer_at_, n);
      return;
    }
    if (n >= kBuffer / 2) {  // large reads (chunks) go straight to the caller's string
      out.resize(n);
      readAt(offset, out.data(), n);
      return;
    }
    buffer_at_ = offset;
    buffer_.resize(static_cast<std::size_t>(std::min<std::uint64_t>(kBuffer, size_ - offset)));
    readAt(offset, buffer_.data(), buffer_.size());
    out.assign(buffer_, 0, n);
  }

 private:
  static constexpr std::size_t kBuffer = std::size_t{1} << 20;

  void readAt(std::uint64_t offset, char* to, std::size_t n) {
    while (n > 0) {
      const ssize_t got = ::pread(fd_, to, n, static_cast<off_t>(offset));
      if (got < 0 && errno == EINTR) continue;
      if (got <= 0)
        throw InputError(name_ + ": offset " + std::to_string(offset),
                         got < 0 ? std::string("read failed: ") + std::strerror(errno)
                                 : std::string("file shrank while reading"));
      to += got;
      n -= static_cast<std::size_t>(got);
      offset += static_cast<std::uint64_t>(got);
    }
  }

  std::string name_;
  int fd_ = -1;
  std::uint64_t size_ = 0;
  std::string buffer_;
  std::uint64_t buffer_at_ = 0;
};

class MemorySource final : public ByteSource {
 public:
  MemorySource(std::string_view bytes, std::string name) : bytes_(bytes), name_(std::move(name)) {}
  const std::string& name() const override { return name_; }
  std::uint64_t size() const override { return bytes_.size(); }
  void read(std::uint64_t offset, std::size_t n, std::string& out) override {
    out.assign(bytes_.substr(static_cast<std::size_t>(offset), n));
  }

 private:
  std::string_view bytes_;
  std::string name_;
};

}  // namespace

std::unique_ptr<ByteSource> openFileSource(const std::filesystem::path& file,
                                           const std::string& name) {
  return std::make_unique<FileSource>(file, name);
}

std::unique_ptr<ByteSource> memorySource(std::string_view bytes, std::string name) {
  return std::make_unique<MemorySource>(bytes, std::move(name));
}

}  // namespace slamprep::eval
