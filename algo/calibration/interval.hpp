#pragma once
// Calibration intervals: what the robot's wheels did between two instants and how the lidar moved
// over the same time. Every calibration method consumes a list of these.

#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

#include "slamprep/algo/calibration/motion_model.hpp"
#include "slamprep/core/diff_drive.hpp"
#include "slamprep/core/samples.hpp"
#include "slamprep/core/se2.hpp"
#include "slamprep/core/time_series.hpp"

namespace slamprep::algo {

/// Wheel motion and measured lidar motion over [t_start_s, t_end_s].
struct CalibrationInterval {
  double t_start_s = 0.0;
  double t_end_s = 0.0;
  /// The encoder steps inside the interval, in time order; their dt_s sum to the duration.
  std::vector<EncoderStep> steps;
  /// Measured motion of the lidar (scan matching, or ground truth for an oracle run).
  SE2 T_lidarStart_lidarEnd;

  double duration_s() const { return t_end_s - t_start_s; }
  double sumLeft_rad() const;   ///< total left wheel rotation
  double sumRight_rad() const;  ///< total right wheel rotation
  /// Censi's phi_l = sum dphi_l / T.
  double meanRateLeft_radps() const { return sumLeft_rad() / duration_s(); }
  /// Censi's phi_r = sum dphi_r / T.
  double meanRateRight_radps() const { return sumRight_rad() / duration_s(); }
};

/// The intervals with their measured motion moved from the lidar to the base frame through a
/// known mount: T_baseStart_baseEnd = T_base_lidar T_lidarStart_lidarEnd T_base_lidar^-1.
std::vector<CalibrationInterval> inBaseFrame(std::vector<CalibrationInterval> intervals,
                                             const SE2& T_base_lidar);

/// Base motion T_baseStart_baseEnd over an interval with a given geometry (exact arcs).
SE2 integrateInterval(const CalibrationInterval& interval, const DiffDriveParams& geometry);

/// How intervals are cut from a log. The defaults are the one policy `slamprep calibrate` and the
/// bench share: one interval per pair of consecutive lidar poses (per scan match). Keyframes end
/// where the noisy measured motion crosses a threshold, which biased the scale (ceres r_L -0.10 %
/// at 5 cm / 5 deg), and tripled model-based's off-centre-lidar bias (docs/calibration.md).
struct IntervalParams {
  /// Start a new interval once the lidar moved this far from the keyframe (0: every pose).
  double keyframe_translation_m = 0.0;
  /// ... or turned this much (0: every pose). Either threshold closes the interval.
  double keyframe_rotation_rad = 0.0;
  /// An interval in which both wheels turned less than this counts as standing still; dropped.
  double standstill_wheel_rad = 1e-3;
};

/// Intervals cut from a log and what was dropped.
struct IntervalSet {
  std::vector<CalibrationInterval> intervals;
  int dropped_standstill = 0;  ///< robot stood still
  int dropped_uncovered = 0;   ///< encoder log did not cover the interval
};

/// Cuts intervals between poses of `T_world_lidar` (scan stamps from ground truth, scan matching
/// or any other motion source): consecutive poses, or keyframes every N m / rad. Encoder steps are
/// cut at the interval ends assuming a constant wheel rate within a step.
IntervalSet buildIntervals(const EncoderLog& encoders, int ticks_per_revolution,
                           const PoseSeries& T_world_lidar, const IntervalParams& params = {});

/// Encoder steps between t0 and t1 (constant rate within a recorded step); empty when the log
/// does not cover [t0, t1].
std::vector<EncoderStep> encoderStepsBetween(const EncoderLog& encoders, int ticks_per_revolution,
                                             double t0_s, double t1_s);

/// Reads Censi's interval records, JSON objects one per line:
/// {"T": s, "phi_l": rad/s, "phi_r": rad/s, "sm": [x, y, th]}. A line may hold several objects
/// one after another (Censi's published lstraight.tuple does on its line 1082). Each becomes one
/// interval with a single constant-rate step; intervals are laid end to end from t = 0. Other
/// keys are ignored. Throws InputError("source:line", ...) on a malformed record ("source:line
/// record k" on a line of several).
std::vector<CalibrationInterval> readIntervalRecords(std::istream& in, const std::string& source);
std::vector<CalibrationInterval> readIntervalRecords(const std::filesystem::path& path);

/// Writes intervals as Censi records (mean rates: sub-step detail is not representable).
void writeIntervalRecords(std::ostream& out, const std::vector<CalibrationInterval>& intervals);
void writeIntervalRecords(const std::filesystem::path& path,
                          const std::vector<CalibrationInterval>& intervals);

}  // namespace slamprep::algo
