#pragma once
// Odometry that stops updating while the robot moves and then catches up in one step (a driver
// repeating its last value, a frozen joint stream): such a run is missing data, not "no motion".
// The rule (docs/export.md, "Stale odometry"): a run of >= 2 consecutive samples with exactly the
// same value, followed by a step larger than the robot's robust typical speed (the 95th
// percentile of |step| / dt over the moving steps of the log, translation and rotation, or each
// wheel, separately) could cover in 3 sample periods (the median dt), is stale: its samples after
// the first are dropped, so the odometry is interpolated over the gap. A repeat followed by an
// ordinary step (the robot standing, then starting) is kept.

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "slamprep/core/samples.hpp"
#include "slamprep/core/time_series.hpp"

namespace slamprep::eval {

struct StaleParams {
  double speed_percentile = 0.95;  ///< the robust typical speed
  double periods = 3.0;            ///< how many sample periods of it the catch-up may cover
  std::size_t min_run = 2;         ///< samples with the same value, the first included
  /// Below these a step is never "too large" (a log whose robot never turns has a 0 rotation
  /// speed): 1 mm and 1 mrad (or 1 mrad of wheel angle).
  std::array<double, 2> floor = {1e-3, 1e-3};
};

/// One stale run: samples [first, first + repeats] hold the same value; the next one jumps.
struct StaleRun {
  std::size_t first = 0;
  std::size_t repeats = 0;          ///< samples dropped (the run's samples after the first)
  double start_s = 0.0;             ///< stamp of the run's first sample
  double span_s = 0.0;              ///< from it to the catch-up sample
  std::array<double, 2> jump = {};  ///< the catch-up step (m and rad, or rad per wheel)
};

/// What the check found in one odometry stream.
struct StaleReport {
  std::string stream;  ///< e.g. "Odometry /odom", "JointState /joint_states"
  std::array<std::string, 2> units = {"m", "rad"};
  std::size_t samples = 0;               ///< before dropping
  std::size_t repeated_runs = 0;         ///< runs of >= 2 equal samples, stale or not
  std::array<double, 2> threshold = {};  ///< the largest ordinary catch-up step
  std::vector<StaleRun> runs;            ///< the stale ones
  std::size_t dropped() const;
  const StaleRun* longest() const;  ///< by span; null when none
  std::string text() const;         ///< one line for the import summary
};

/// Marks the stale runs. `same[k]`: sample k holds exactly sample k-1's value; `step[k]`: the
/// two magnitudes of the step from k-1 to k (k >= 1; entry 0 unused).
std::vector<StaleRun> findStaleRuns(const std::vector<double>& stamps,
                                    const std::vector<std::array<double, 2>>& step,
                                    const std::vector<char>& same, const StaleParams& params,
                                    std::array<double, 2>& threshold, std::size_t& repeated_runs);

/// Poses (T_odom_base) without their stale samples; translation and rotation steps.
PoseSeries dropStaleOdometry(const PoseSeries& poses, StaleReport& report,
                             const StaleParams& params = {});

/// Wheel ticks without their stale samples; left and right wheel angle steps.
EncoderLog dropStaleEncoders(const EncoderLog& encoders, double rad_per_tick, StaleReport& report,
                             const StaleParams& params = {});

}  // namespace slamprep::eval
