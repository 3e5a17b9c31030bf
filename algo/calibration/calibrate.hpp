#pragma once
// One entry point for every calibration method: the method by its enum, the inputs all methods
// draw from, one result type, and the best available result (calibration_method.hpp's rule).

#include <optional>
#include <string>
#include <vector>

#include "slamprep/algo/calibration/calibration_method.hpp"
#include "slamprep/algo/calibration/calibration_result.hpp"
#include "slamprep/algo/calibration/ceres_refine.hpp"
#include "slamprep/algo/calibration/direct_linear.hpp"
#include "slamprep/algo/calibration/interval.hpp"
#include "slamprep/algo/calibration/joint_censi.hpp"
#include "slamprep/algo/calibration/model_based.hpp"
#include "slamprep/algo/calibration/mount_prior.hpp"
#include "slamprep/algo/calibration/robust_trim.hpp"
#include "slamprep/algo/calibration/umbmark.hpp"

namespace slamprep::algo {

/// What the methods consume; each takes its part.
struct CalibrationInput {
  std::vector<CalibrationInterval> intervals;  ///< direct, model, joint, ceres
  /// Geometry the odometry was integrated with: direct's u_i, umbmark's corrected base.
  std::optional<DiffDriveParams> nominal;
  std::vector<UmbmarkRun> umbmark_runs;  ///< umbmark
  /// Spans whose interval headings loop closures corrected (joint and ceres propagate it into
  /// their covariance); empty when the intervals are as matched.
  std::vector<LoopSpan> heading_loops;
  /// The lidar mount taken as known by the methods that do not estimate one (direct, model):
  /// their intervals' lidar motion is first expressed in the base frame with it
  /// (inBaseFrame). nullopt: the lecture's assumption, the lidar at the robot centre.
  std::optional<SE2> known_T_base_lidar;
  /// The mount the recording came with, fused into the fits that estimate one (joint, ceres)
  /// before they are judged undetermined (mount_prior.hpp); nullopt: the intervals alone.
  std::optional<MountPrior> mount_prior;
};

/// Every method's parameters. ceres starts from `joint` (its `start` is ignored); direct and
/// umbmark take their nominal geometry from the input.
struct CalibrationParams {
  /// Robust screening of the intervals, applied around every interval method (robust_trim.hpp).
  TrimParams trim;
  /// An interval method whose 1-sigma of r_L, r_R or b exceeds this fraction of the estimate is
  /// refused as undetermined: beyond the 15 % that flags an estimate (nominal_flags.hpp) the
  /// data cannot tell a good geometry from a flagged one. 0: never.
  double max_relative_sigma = 0.15;
  DirectLinearParams direct;
  ModelBasedParams model;
  JointParams joint;
  CeresParams ceres;
  UmbmarkParams umbmark;
};

/// One method's outcome.
struct CalibrationRun {
  CalibrationMethod method = CalibrationMethod::kDirect;
  CalibrationResult result;
  /// ceres with estimate_time_offset, when ok: t_lidar - t_encoder and its 1-sigma.
  std::optional<double> time_offset_s;
  double time_offset_sigma_s = 0.0;
  /// Set when the wheel increments were derived from odometry poses (a log without encoder
  /// ticks): the nominal geometry they were derived with. The estimates are then the log's
  /// odometry geometry corrected: estimate / nominal is the factor to apply to whatever geometry
  /// the robot's odometry used (docs/calibration.md, "Logs without encoder ticks").
  std::optional<DiffDriveParams> relative_to_odometry;
  /// joint or ceres with CalibrationInput::mount_prior: what the prior did (applied or not).
  std::optional<MountPriorUse> mount_prior;
  /// joint or ceres with estimate_sideslip, when ok: the sideslip k (s) and its 1-sigma.
  std::optional<double> sideslip_s;
  double sideslip_sigma_s = 0.0;
};

/// Why `method` does not apply to `input` (umbmark without square runs, direct without the
/// nominal geometry); nullopt when its input is there. calibrate() refuses with this reason.
std::optional<std::string> missingInput(CalibrationMethod method, const CalibrationInput& input);

/// Runs one method. A method whose input is missing refuses (ok = false, reason says which).
/// Interval methods are fitted, their intervals screened against the fit and the fit repeated
/// on the kept ones until the kept set repeats (robust_trim.hpp); when nothing is dropped the
/// result is the plain fit, bit for bit.
CalibrationRun calibrate(CalibrationMethod method, const CalibrationInput& input,
                         const CalibrationParams& params = {});

/// Runs `methods` in the given order; joint runs once when both joint and ceres are asked for
/// (ceres starts from it, as it would on its own).
std::vector<CalibrationRun> calibrate(const std::vector<CalibrationMethod>& methods,
                                      const CalibrationInput& input,
                                      const CalibrationParams& params = {});

/// The best available result: the first ok run in calibrationPreference() order (the first
/// such run when a method appears twice); nullptr when none is ok.
const CalibrationRun* bestRun(const std::vector<CalibrationRun>& runs);

}  // namespace slamprep::algo
