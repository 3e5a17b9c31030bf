#pragma once
// De-skew every scan of a dataset with one method, and measure it against the ground-truth
// undistorted points when the dataset has them. Shared by `slamprep bench` and the CLI.

#include <optional>
#include <string>
#include <vector>

#include "algo/deskew/sequence.hpp"
#include "core/dataset.hpp"
#include "eval/metrics/error_stats.hpp"

namespace slamprep::eval {

struct DatasetDeskewOptions {
  /// Wheel geometry the odometry-based methods integrate the encoders with.
  DiffDriveParams geometry;
  /// Lidar mount the odometry-based and oracle methods use.
  SE2 T_base_lidar;
  /// Which instant the corrected points describe.
  algo::ReferenceTime reference = algo::ReferenceTime::kFirst;
  /// Method parameters (point-to-line ICP inside vicp and odom-icp, quadratic pieces, ...).
  algo::DeskewSequenceParams params;
};

/// Options that use what the robot believes: nominal geometry, the dataset's mount.
DatasetDeskewOptions nominalDeskewOptions(const Dataset& dataset);

struct DatasetDeskew {
  std::vector<algo::DeskewResult> scans;  ///< one per dataset scan, in order
  int refused = 0;                        ///< scans the method refused
  std::string first_reason;               ///< why the first refused scan was refused
  double seconds = 0.0;                   ///< wall-clock time of the method alone
  /// Distance of each corrected point to the true undistorted point of its beam, over all
  /// scans; nullopt without ground truth.
  std::optional<ErrorStats> error_m;
};

/// Runs `method` over the scans in order (stateful methods see the previous scan).
DatasetDeskew deskewDataset(const Dataset& dataset, algo::DeskewMethod method,
                            const DatasetDeskewOptions& options);

/// Every scan's corrected points (valid beams only), e.g. to scan-match de-skewed scans.
std::vector<Points2> correctedPoints(const DatasetDeskew& deskewed);

}  // namespace slamprep::eval
