#pragma once
// What the export tests share: a synthetic ExportInput.

#include "slamprep/eval/formats/export.hpp"
#include "synthetic_dataset.hpp"

namespace slamprep::test {

inline eval::ExportInput syntheticInput() {
  eval::ExportInput in;
  in.dataset = makeSyntheticDataset();
  in.deskewed["linear"] = in.dataset.scans;  // stands in for a de-skew output
  in.calibration = eval::CalibrationChoice{*in.dataset.info.true_geometry, "joint", std::nullopt};
  return in;
}

}  // namespace slamprep::test
