#pragma once
// De-skew every scan of a dataset with one method, and measure it against the ground-truth
// undistorted points when the dataset has them. Shared by `slamprep bench` and the CLI.

#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "slamprep/algo/deskew/sequence.hpp"
#include "slamprep/core/dataset.hpp"
#include "slamprep/eval/metrics/error_stats.hpp"

namespace slamprep::eval {

struct DatasetDeskewOptions {
  /// Wheel geometry the odometry-based methods integrate the encoders with.
  DiffDriveParams geometry;
  /// Odometry to use as it is instead of the encoders integrated with `geometry` (an imported
  /// log has odometry but may have no encoders).
  std::optional<PoseSeries> odometry;
  /// Lidar mount the odometry-based methods use (the oracle always uses the dataset's own).
  SE2 T_base_lidar;
  /// The scans' stamps mark their last beam instead of their first.
  bool stamp_is_last_beam = false;
  /// Only scans stamped in [from, to] count in the error figures (all are de-skewed).
  double measure_from_s = -std::numeric_limits<double>::infinity();
  double measure_to_s = std::numeric_limits<double>::infinity();
  /// False: the scans are de-skewed and not measured against the truth (no error figures),
  /// for a caller that wants the points only (a matcher): the truth's ray casts and the
  /// figures' sorting were about a sixth of a twin test's time.
  bool measure_errors = true;
  /// Which instant the corrected points describe.
  algo::ReferenceTime reference = algo::ReferenceTime::kFirst;
  /// Method parameters (point-to-line ICP inside vicp and odom-icp, quadratic pieces, ...).
  algo::DeskewParams params;
  /// Called after every scan with (scans done, all scans): progress only, never the results.
  std::function<void(std::size_t, std::size_t)> on_scan;
};

/// Options that use what the robot believes: nominal geometry, the dataset's mount.
DatasetDeskewOptions nominalDeskewOptions(const Dataset& dataset);

/// One scan a method refused: which, why (a countable name) and the message.
struct ScanRefusal {
  std::size_t scan = 0;  ///< index in the dataset
  algo::DeskewRefusal reason = algo::DeskewRefusal::kNone;
  std::string detail;
};

struct DatasetDeskew {
  std::vector<algo::DeskewResult> scans;  ///< one per dataset scan, in order
  int refused = 0;                        ///< scans the method refused
  std::vector<ScanRefusal> refusals;      ///< every refused scan, in order
  std::string first_reason;               ///< why the first refused scan was refused
  std::size_t warnings = 0;               ///< warnings over all scans
  std::string first_note;                 ///< "scan k: ..." of the first refusal or warning
  double seconds = 0.0;                   ///< wall-clock time of the method alone
  /// Distance of each corrected point to the true undistorted point of its beam, over all
  /// scans; nullopt without ground truth.
  std::optional<ErrorStats> error_m;
  /// The same error split by its cause (docs/metrics.md, "De-skew error"): the part the
  /// method's rotation error explains and the part its translation error explains.
  std::optional<ErrorStats> rotation_induced_m;
  std::optional<ErrorStats> translation_induced_m;
  /// max over beams of what the split leaves unexplained (range noise: the truth is noiseless).
  double max_split_residual_m = 0.0;
  /// The repacked scans (DeskewResult::repacked) against the true points repacked onto the same
  /// grid the same way, per grid ray over all measured scans; nullopt without truth or repacking.
  std::optional<ErrorStats> repacked_error_m;
  /// Grid rays of the measured scans where the truth has a range and the repacked scan none.
  std::size_t repacked_lost_beams = 0;
  /// error_m over every measured scan with a refused one counted as measured (method none's
  /// error on it), as `slamprep match --deskew` keeps it: comparable between methods that refuse
  /// different scans. nullopt without truth.
  std::optional<ErrorStats> fallback_error_m;
};

/// Refused scans counted by reason name ("not-bracketed": 3), names sorted.
std::map<std::string, int> refusedByReason(const std::vector<ScanRefusal>& refusals);

/// Runs `method` over the scans in order (stateful methods see the previous scan).
DatasetDeskew deskewDataset(const Dataset& dataset, algo::DeskewMethod method,
                            const DatasetDeskewOptions& options);

/// Every scan's corrected points (valid beams only), e.g. to scan-match de-skewed scans.
std::vector<Points2> correctedPoints(const DatasetDeskew& deskewed);

}  // namespace slamprep::eval
