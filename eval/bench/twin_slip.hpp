#pragma once
// Random wheel slip as a twin fits it (docs/twin.md, "Wheel slip"): the heading the wheels
// integrate with the true geometry, against a reference heading (the matched trajectory of a
// recording, the ground truth of a simulation), over pieces of path.

#include <cstddef>
#include <vector>

#include "slamprep/core/diff_drive.hpp"
#include "slamprep/core/time_series.hpp"
#include "slamprep/eval/formats/wheel_odometry.hpp"

namespace slamprep::eval {

struct WheelSlipParams {
  /// Durations of the pieces, each cut one after another along the recording: time, not path,
  /// so that turns on the spot count. Several, because the slip's variance grows with the
  /// duration and the reference's own noise does not: that is what tells them apart.
  std::vector<double> piece_s = {1.5, 3.0, 6.0, 12.0};
  /// The correlation time the simulator is given: pieces longer than it see mostly sigma^2 tau,
  /// so sigma is fitted at this tau.
  double tau_s = 0.5;
  double max_heading_error_deg = 45.0;  ///< beyond: a failed match or a held robot, not slip
  /// After a first fit, a piece whose error is beyond this many of its predicted sigmas is
  /// left out and the fit repeated (a Gaussian loses 0.3 % of its pieces at 3).
  double outlier_sigmas = 3.0;
  double max_gap_s = 1.0;      ///< a piece with a longer step of the reference is not used
  std::size_t min_pieces = 8;  ///< fewer: no fit (sigma 0)
};

struct WheelSlipFit {
  std::size_t pieces = 0;  ///< pieces used
  bool fitted = false;     ///< at least min_pieces
  double sigma = 0.0;      ///< stationary sigma of the slip s at tau_s (0: none seen)
  /// Heading noise per piece that does not grow with the wheels' motion: the reference's own.
  double reference_noise_rad = 0.0;
  double tau_s = 0.0;
};

/// Least squares of the pieces' (all durations) squared heading error on what the slip model
/// predicts for them:
///   E[dtheta_k^2] = sigma^2 Q_k + c,                                                     (1)
///   Q_k = (2 tau / b^2) (1 - (tau / T)(1 - exp(-T / tau))) sum_steps (ds_L^2 + ds_R^2) / dt,
/// (1): dtheta = (r_R int w_R s_R dt - r_L int w_L s_L dt) / b, and for a stationary
/// Ornstein-Uhlenbeck s and a constant speed v over a piece of duration T,
/// Var(int v s dt) = 2 sigma^2 tau v^2 T (1 - (tau / T)(1 - exp(-T / tau)));
/// c >= 0 is the reference's heading noise. sigma^2 < 0 fits as no slip.
WheelSlipFit fitWheelSlip(const OdometryEncoders& encoders, const DiffDriveParams& true_geometry,
                          const PoseSeries& T_world_base_reference,
                          const WheelSlipParams& params = {});

}  // namespace slamprep::eval
