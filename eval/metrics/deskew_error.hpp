#pragma once
// De-skew error per beam, and its split into rotation- and translation-induced parts
// (docs/metrics.md, "De-skew error").

#include <optional>
#include <string>
#include <vector>

#include "slamprep/core/se2.hpp"
#include "slamprep/eval/metrics/error_stats.hpp"

namespace slamprep::eval {

using BeamPoints = std::vector<std::optional<Eigen::Vector2d>>;

/// Pose error of one beam: Delta_i = T_ref_beam_est * T_ref_beam_true^-1, where T_ref_beam maps
/// the lidar frame at the beam's time into the lidar frame at the reference time (what de-skew
/// assumed vs the truth). Then p_corrected = Delta_i p_true whenever both used the same range.
SE2 beamPoseError(const SE2& T_ref_beam_est, const SE2& T_ref_beam_true);

struct DeskewErrorResult {
  bool ok = false;
  std::string reason;
  std::size_t compared = 0;      ///< beams with both a corrected and a true point
  std::size_t missing = 0;       ///< true point but no corrected one (de-skew dropped it)
  std::size_t extra = 0;         ///< corrected point but no true one
  ErrorStats error_m;            ///< |p_corrected - p_true| per compared beam
  std::vector<double> errors_m;  ///< per compared beam, in beam order
  /// Filled when per-beam pose errors were given:
  bool has_split = false;
  ErrorStats rotation_induced_m;             ///< |(R(Delta_i) - I) p_true| per compared beam
  ErrorStats translation_induced_m;          ///< |t(Delta_i)| per compared beam
  std::vector<double> rotation_errors_m;     ///< per compared beam, in beam order
  std::vector<double> translation_errors_m;  ///< per compared beam, in beam order
  /// max over beams of |(p_corrected - p_true) - (rotation part + translation part)|: 0 when the
  /// pose errors explain the corrected points (same range, no repacking onto a beam grid).
  double max_split_residual_m = 0.0;
};

/// Compares corrected points with the ground-truth undistorted points (ScanRecord::p_ref_true),
/// beam by beam; `beam_pose_errors` (one Delta_i per beam, see beamPoseError) is optional.
/// Refuses mismatched sizes and scans with no beam to compare.
DeskewErrorResult deskewError(const BeamPoints& p_corrected, const BeamPoints& p_true,
                              const std::vector<SE2>& beam_pose_errors = {});

/// A repacked scan against the true points repacked onto the same grid the same way, ray by
/// ray (docs/metrics.md, "Repacked de-skew error"). Both points of ray j lie on the ray, so their
/// distance is |r_j - r_true_j|.
struct RepackedErrorResult {
  std::vector<double> errors_m;  ///< per grid ray where both have a range, in ray order
  std::size_t lost = 0;          ///< rays where only the truth has a range
  std::size_t extra = 0;         ///< rays where only the repacked scan has one
};

/// One range per grid ray each (+inf: no range); sizes must match (empty result otherwise).
RepackedErrorResult repackedError(const std::vector<double>& ranges_m,
                                  const std::vector<double>& true_ranges_m);

}  // namespace slamprep::eval
