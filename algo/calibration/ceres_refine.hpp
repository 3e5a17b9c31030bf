#pragma once
// Nonlinear refinement of all six parameters (r_L, r_R, b, l_x, l_y, l_yaw), optionally plus a
// constant clock offset between encoders and lidar or a sideslip in turns, with Ceres; starts
// from the joint closed form.

#include <vector>

#include "slamprep/algo/calibration/joint_censi.hpp"

namespace slamprep::algo {

struct CeresParams {
  /// Also estimate offset_s = t_lidar - t_encoder (the encoder window is shifted by -offset).
  bool estimate_time_offset = false;
  /// Also estimate a sideslip k (s): the base moves sideways at v_y = k v w, as tyres do in
  /// turns (docs/calibration.md, "Sideslip"). Not together with the time offset.
  bool estimate_sideslip = false;
  /// Huber loss threshold on the whitened residual, in standard deviations.
  double huber_sigmas = 3.0;
  /// Solver iteration limit.
  int max_iterations = 100;
  /// Refuse when the whitened, column-equilibrated Jacobian is worse conditioned than this.
  /// 1e3: well-excited drives score 2-20; a single-curvature circle scores 1e3-1e4 and
  /// gives 20 % errors there (measured in the default suite).
  double max_condition_number = 1e3;
  /// Lower bound on the noise used for whitening (keeps noiseless data well scaled).
  double min_sigma = 1e-9;
  /// Spans whose headings loop closures corrected: the heading rows' covariance propagates the
  /// correction (loop_covariance.hpp). Empty: intervals as matched.
  std::vector<LoopSpan> heading_loops;
  /// Closed-form start (method 3).
  JointParams start;
};

struct CeresResult : CalibrationResult {
  double time_offset_s = 0.0;        ///< estimated offset (0 when not estimated)
  double time_offset_sigma_s = 0.0;  ///< its 1-sigma
  double sideslip_s = 0.0;           ///< estimated sideslip k (0 when not estimated)
  double sideslip_sigma_s = 0.0;     ///< its 1-sigma
  /// Residual noise per axis of the SE(2) log residual (x m, y m, theta rad), re-estimated.
  Eigen::Vector3d sigma_residual = Eigen::Vector3d::Zero();
  std::string termination;  ///< Ceres termination type
};

/// Minimises sum_k rho(|W log(pred_k^-1 * sm_k)|^2) over the parameters (Huber rho, W the
/// inverse noise per axis), where pred_k = l^-1 * o_k(r_L, r_R, b, offset) * l. Runs the
/// closed-form joint method first (on all intervals) and refines from it; covariance from
/// ceres::Covariance (the inverse Fisher information of the whitened problem).
CeresResult calibrateCeres(const std::vector<CalibrationInterval>& intervals,
                           const CeresParams& params = {});

/// Same, starting from a given joint result (must be ok) on the same intervals.
CeresResult calibrateCeres(const std::vector<CalibrationInterval>& intervals,
                           const JointResult& start, const CeresParams& params = {});

}  // namespace slamprep::algo
