#pragma once
// Random wheel slip, and slip in turns, as a twin fits it (docs/twin.md, "Wheel slip"): the heading
// the wheels integrate with the true geometry, against a reference heading (the matched trajectory
// of a recording, the ground truth of a simulation), over pieces of path.

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
  std::vector<double> piece_s = {0.75, 1.5, 3.0, 6.0, 12.0};
  /// The correlation time the simulator is given: pieces longer than it see mostly sigma^2 tau,
  /// so sigma is fitted at this tau.
  double tau_s = 0.5;
  double max_heading_error_deg = 45.0;  ///< beyond: a failed match or a held robot, not slip
  /// After a first fit, a piece whose error is beyond this many of its predicted sigmas is
  /// left out and the fit repeated, until none is (a Gaussian loses 0.3 % of its pieces at 3).
  double outlier_sigmas = 3.0;
  double max_gap_s = 1.0;      ///< a piece with a longer step of the reference is not used
  std::size_t min_pieces = 8;  ///< fewer: no fit (sigma 0)
  /// No piece's predicted heading sigma is weighed as less than this (1 mrad, 0.06 deg: below
  /// what any reference resolves); else pieces the fit predicts as exact (straight driving
  /// without wheel slip, against a simulation's truth) outweigh every other.
  double min_sigma_rad = 1e-3;
  double rate_span_s = 0.2;  ///< the turn rate at a piece's ends, over this span of the wheels
  /// The timing is fitted only where it raises the pieces' likelihood (each stretch counted
  /// once) by this likelihood ratio: chi2 with 1 degree of freedom at p = 0.001.
  double timing_likelihood_ratio = 10.83;
  /// The distance fit (Eq. 2) takes pieces that turn less than this: a turn moves a lidar told
  /// off its true mount along a chord the base does not, which is not slip.
  double max_distance_turn_deg = 30.0;
  double max_distance_error_m = 0.5;  ///< beyond: a failed match or a held robot, not slip
  double min_sigma_m = 1e-3;          ///< as min_sigma_rad, for the distance (1 mm)
  /// The common slip is fitted only where it raises the distance pieces' likelihood (each
  /// stretch counted once) by this likelihood ratio, as the timing is.
  double common_likelihood_ratio = 10.83;
  /// Eq. (1)'s variances held, not fitted, where >= 0 (< 0: fitted): the reference's own heading
  /// noise per piece c, the wheel slip and the turn slip. A twin holds its recording's c at what
  /// the twin's own scans show and the slips at the recording's: a robot turning steadily (a
  /// wall or person follower) turns as fast at every piece's ends, so the timing's W_k is about
  /// constant and c, fitted free, takes the timing; held, the timing takes what c did beyond it.
  double reference_noise_rad = -1.0;
  double slip_sigma = -1.0;
  double turn_slip_sigma = -1.0;
};

struct WheelSlipFit {
  std::size_t pieces = 0;        ///< pieces used
  bool fitted = false;           ///< at least min_pieces
  double sigma = 0.0;            ///< stationary sigma of the slip s at tau_s (0: none seen)
  double turn_sigma = 0.0;       ///< stationary sigma of the turn slip u at tau_s (0: none seen)
  double timing_jitter_s = 0.0;  ///< sigma of when the wheels are read against their stamps
  /// 2 (log L with the timing - log L without it), each stretch of pieces counted once: the
  /// timing is kept (timing_jitter_s > 0) only beyond WheelSlipParams::timing_likelihood_ratio.
  double timing_likelihood_ratio = 0.0;
  /// Heading noise per piece that does not grow with the wheels' motion: the reference's own
  /// (sigma, turn_sigma and this: WheelSlipParams's where held).
  double reference_noise_rad = 0.0;
  double tau_s = 0.0;
  /// Slip both wheels share (Eq. 2): the distance the wheels count against the reference's, with
  /// the wheel slip above taken as known.
  std::size_t distance_pieces = 0;  ///< pieces used
  bool common_fitted = false;       ///< at least min_pieces
  double common_sigma = 0.0;        ///< stationary sigma of the common slip c at tau_s
  /// 2 (log L with the common slip - log L without it), as timing_likelihood_ratio: the slip is
  /// kept (common_sigma > 0) only beyond WheelSlipParams::common_likelihood_ratio.
  double common_likelihood_ratio = 0.0;
  double reference_distance_noise_m = 0.0;  ///< the reference's own, per piece
};

/// What a slip fit reads: the wheels, the geometry they are integrated with, and the reference
/// heading on the wheels' clock.
struct WheelSlipInput {
  OdometryEncoders encoders;
  DiffDriveParams geometry;
  PoseSeries T_world_base_reference;
};

/// Least squares of the pieces' (all durations) squared heading error on what the slip model
/// predicts for them:
///   E[dtheta_k^2] = sigma^2 Q_k + sigma_turn^2 Q_turn,k + sigma_t^2 W_k + c,              (1)
///   Q_k = (S(ds_L) + S(ds_R)) / b^2,  Q_turn,k = S(dtheta),  W_k = omega_0^2 + omega_1^2,
///   S(a) = sum_i sum_j a_i a_j exp(-|t_i - t_j| / tau)  over the piece's encoder steps,
/// (1): the wheels count (1 + s_i) of what they rolled and (1 + u) of the turn they made
/// (sim::WheelSlip: s_L, s_R, u Ornstein-Uhlenbeck processes of correlation time tau, held over
/// each encoder step), so the heading error is (sum ds_R s_R - sum ds_L s_L) / b + sum dtheta u,
/// whose variance S gives; a wheel reading e off its stamp (independent, sigma_t) errs by
/// omega e at each end of the piece (omega: the wheels' turn rate there); c is the reference's
/// heading noise. Every variance >= 0 (a negative one fits as none). Wheel slip grows with the
/// distance driven, turn slip with the turning, timing with the turn rate where a piece starts
/// and ends whatever it turned between: a robot that slips in its turns and not on the straight
/// is told apart, and one whose wheels and scans are paired at varying times from both.
///
/// The distance both wheels count, against the reference's chord, over the pieces that turn
/// little, by the same maximum likelihood:
///   E[dd_k^2] = sigma_c^2 C_k + k_w W_k + sigma_v^2 V_k + c_d + sigma^2 R_k / 4,           (2)
///   C_k = S(m a),  R_k = S(ds_L a) + S(ds_R a),  m = (ds_L + ds_R) / 2,
///   a_i = cos(theta_i - phi),  V_k = v_0^2 + v_1^2,
/// dd = |p_odometry(t1) - p_odometry(t0)| - |p_reference(t1) - p_reference(t0)|: both wheels
/// count (1 + c) of their common part (sim::WheelSlip), which lengthens each step m by c m, and
/// the chord by its share a along the chord's direction phi. The last term is what the heading
/// fit's wheel slip adds (held, not refitted: on the straight a wheel's own slip and the common
/// one are the same to the distance). The others are the reference's: W = omega_0^2 + omega_1^2
/// (a scan taken while turning is matched a little off), V with v the speed along the chord at
/// the ends (scans and wheels paired at varying times), c_d a constant. A common slip leaves
/// every heading as it was, so Eq. (1) never sees it.
WheelSlipFit fitWheelSlip(const OdometryEncoders& encoders, const DiffDriveParams& true_geometry,
                          const PoseSeries& T_world_base_reference,
                          const WheelSlipParams& params = {});
inline WheelSlipFit fitWheelSlip(const WheelSlipInput& in, const WheelSlipParams& params = {}) {
  return fitWheelSlip(in.encoders, in.geometry, in.T_world_base_reference, params);
}

}  // namespace slamprep::eval
