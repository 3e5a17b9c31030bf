#include "slamprep/eval/formats/scan_spill.hpp"

#include <array>

#include "slamprep/core/error.hpp"

namespace slamprep::eval {
namespace {

// The fixed fields of a record, then the beam count and the ranges.
constexpr std::size_t kFields = 7;

std::array<double, kFields> fieldsOf(const LaserScan& s) {
  return {s.stamp_s,     s.angle_min_rad, s.angle_increment_rad, s.time_increment_s,
          s.scan_time_s, s.range_min_m,   s.range_max_m};
}

}  // namespace

ScanSpill::ScanSpill(std::filesystem::path file) : file_(std::move(file)) {
  stream_ = std::fopen(file_.c_str(), "w+b");
  if (!stream_) throw InputError(file_.string(), "cannot create the scan spill file");
}

ScanSpill::~ScanSpill() {
  if (stream_) std::fclose(stream_);
  std::error_code ignored;
  std::filesystem::remove(file_, ignored);
}

std::uint64_t ScanSpill::append(const LaserScan& scan) {
  const std::uint64_t offset = size_;
  const auto fields = fieldsOf(scan);
  const std::uint64_t n = scan.ranges_m.size();
  const bool ok = std::fseek(stream_, static_cast<long>(size_), SEEK_SET) == 0 &&
                  std::fwrite(fields.data(), sizeof(double), kFields, stream_) == kFields &&
                  std::fwrite(&n, sizeof n, 1, stream_) == 1 &&
                  std::fwrite(scan.ranges_m.data(), sizeof(double), n, stream_) == n;
  if (!ok) throw InputError(file_.string(), "cannot write the scan spill file (disk full?)");
  size_ += sizeof(double) * (kFields + n) + sizeof n;
  return offset;
}

LaserScan ScanSpill::read(std::uint64_t offset) const {
  std::array<double, kFields> f{};
  std::uint64_t n = 0;
  LaserScan s;
  bool ok = std::fseek(stream_, static_cast<long>(offset), SEEK_SET) == 0 &&
            std::fread(f.data(), sizeof(double), kFields, stream_) == kFields &&
            std::fread(&n, sizeof n, 1, stream_) == 1 && offset + n * sizeof(double) < size_;
  if (ok) {
    s.ranges_m.resize(n);
    ok = std::fread(s.ranges_m.data(), sizeof(double), n, stream_) == n;
  }
  if (!ok) throw InputError(file_.string(), "cannot read back the scan spill file");
  s.stamp_s = f[0];
  s.angle_min_rad = f[1];
  s.angle_increment_rad = f[2];
  s.time_increment_s = f[3];
  s.scan_time_s = f[4];
  s.range_min_m = f[5];
  s.range_max_m = f[6];
  return s;
}

}  // namespace slamprep::eval
