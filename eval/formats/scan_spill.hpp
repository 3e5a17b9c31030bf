#pragma once
// Scans parked on disk while a long bag is imported, so that memory holds the small streams and
// one chunk, not every range (a 2-hour bag's ranges alone are ~0.5 GB as doubles). Binary, this
// process only: written once, read back by offset in any order, deleted with the object.

#include <cstdint>
#include <cstdio>
#include <filesystem>

#include "slamprep/core/laser_scan.hpp"

namespace slamprep::eval {

class ScanSpill {
 public:
  /// Creates (truncates) `file`; throws InputError when it cannot.
  explicit ScanSpill(std::filesystem::path file);
  ~ScanSpill();
  ScanSpill(const ScanSpill&) = delete;
  ScanSpill& operator=(const ScanSpill&) = delete;

  /// Appends a scan; returns where it starts.
  std::uint64_t append(const LaserScan& scan);
  /// The scan that starts at `offset` (a value append returned).
  LaserScan read(std::uint64_t offset) const;

 private:
  std::filesystem::path file_;
  std::FILE* stream_ = nullptr;
  std::uint64_t size_ = 0;
};

}  // namespace slamprep::eval
