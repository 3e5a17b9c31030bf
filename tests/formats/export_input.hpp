#pragma once
// What the export tests share: a synthetic ExportInput and a scratch path per test process.

#include <unistd.h>

#include <filesystem>
#include <string>

#include "eval/formats/export.hpp"
#include "synthetic_dataset.hpp"

namespace slamprep::test {

inline std::filesystem::path scratch(const std::string& name) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("slamprep_formats_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  return dir / name;
}

inline eval::ExportInput syntheticInput() {
  eval::ExportInput in;
  in.dataset = makeSyntheticDataset();
  in.deskewed["linear"] = in.dataset.scans;  // stands in for a de-skew output
  in.calibration = eval::CalibrationChoice{*in.dataset.info.true_geometry, "joint"};
  return in;
}

}  // namespace slamprep::test
