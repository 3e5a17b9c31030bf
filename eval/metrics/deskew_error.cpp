#include "slamprep/eval/metrics/deskew_error.hpp"

#include <algorithm>
#include <cmath>

namespace slamprep::eval {

SE2 beamPoseError(const SE2& T_ref_beam_est, const SE2& T_ref_beam_true) {
  return T_ref_beam_est * T_ref_beam_true.inverse();
}

DeskewErrorResult deskewError(const BeamPoints& p_corrected, const BeamPoints& p_true,
                              const std::vector<SE2>& beam_pose_errors) {
  DeskewErrorResult r;
  if (p_corrected.size() != p_true.size()) {
    r.reason = "corrected scan has " + std::to_string(p_corrected.size()) +
               " beams, ground truth " + std::to_string(p_true.size());
    return r;
  }
  r.has_split = !beam_pose_errors.empty();
  if (r.has_split && beam_pose_errors.size() != p_true.size()) {
    r.reason = "need one pose error per beam (" + std::to_string(p_true.size()) + "), got " +
               std::to_string(beam_pose_errors.size());
    return r;
  }
  for (std::size_t i = 0; i < p_true.size(); ++i) {
    if (!p_true[i] || !p_corrected[i]) {
      r.missing += p_true[i] && !p_corrected[i];
      r.extra += !p_true[i] && p_corrected[i];
      continue;
    }
    const Eigen::Vector2d error = *p_corrected[i] - *p_true[i];
    r.errors_m.push_back(error.norm());
    if (!r.has_split) continue;
    // p_corrected - p_true = Delta p - p = (R - I) p + t: the two parts add up exactly.
    const SE2& delta = beam_pose_errors[i];
    const Eigen::Vector2d e_rotation = delta.rotation() * *p_true[i] - *p_true[i];
    const Eigen::Vector2d e_translation = delta.translation();
    r.rotation_errors_m.push_back(e_rotation.norm());
    r.translation_errors_m.push_back(e_translation.norm());
    r.max_split_residual_m =
        std::max(r.max_split_residual_m, (error - e_rotation - e_translation).norm());
  }
  r.compared = r.errors_m.size();
  r.error_m = summarize(r.errors_m);
  if (!r.error_m.ok) {
    r.reason = r.compared == 0 ? "no beam has both a corrected and a true point"
                               : "errors: " + r.error_m.reason;
    return r;
  }
  if (r.has_split) {
    r.rotation_induced_m = summarize(r.rotation_errors_m);
    r.translation_induced_m = summarize(r.translation_errors_m);
    if (!r.rotation_induced_m.ok || !r.translation_induced_m.ok) {
      r.reason = "pose errors are not finite";
      return r;
    }
  }
  r.ok = true;
  return r;
}

RepackedErrorResult repackedError(const std::vector<double>& ranges_m,
                                  const std::vector<double>& true_ranges_m) {
  RepackedErrorResult r;
  if (ranges_m.size() != true_ranges_m.size()) return r;
  for (std::size_t j = 0; j < ranges_m.size(); ++j) {
    const bool has = std::isfinite(ranges_m[j]), has_true = std::isfinite(true_ranges_m[j]);
    if (has && has_true) r.errors_m.push_back(std::abs(ranges_m[j] - true_ranges_m[j]));
    r.lost += has_true && !has;
    r.extra += has && !has_true;
  }
  return r;
}

}  // namespace slamprep::eval
