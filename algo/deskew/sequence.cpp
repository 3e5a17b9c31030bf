#include "slamprep/algo/deskew/sequence.hpp"

namespace slamprep::algo {

DeskewSequence::DeskewSequence(DeskewMethod method, DeskewInputs inputs, DeskewParams params)
    : method_(method), inputs_(std::move(inputs)), params_(std::move(params)) {
  inputs_.previous.reset();
}

DeskewResult DeskewSequence::next(const LaserScan& scan) {
  std::optional<PreviousScan>& previous = inputs_.previous;
  DeskewResult result;
  if (!previous && method_ == DeskewMethod::kVicp) {
    // Nothing to match on the first scan: left as measured, and said so.
    result = deskew(DeskewMethod::kNone, scan, inputs_, params_);
    result.warnings.push_back("vicp: first scan of the sequence, left as measured");
  } else {
    result = deskew(method_, scan, inputs_, params_);
  }
  if (!result.ok) {
    previous.reset();
    return result;
  }
  if (!deskewMethodUsesPreviousScan(method_)) return result;
  PreviousScan next;
  next.scan = scan;
  next.stamp_is_last_beam = inputs_.stamp_is_last_beam;
  next.odometry_error_per_s = result.odometry_error_per_s;
  if (result.twist_lidar) {
    next.twist_lidar = result.twist_lidar;
  } else if (previous && result.match) {
    next.twist_lidar =
        result.match->T_ref_cur.log() /
        (result.first_beam_s - firstBeamTime(previous->scan, previous->stamp_is_last_beam));
  }
  // const-velocity predicts from the previous motion; the motion into this scan is estimated
  // now, for the next one.
  if (previous && !result.twist_lidar && method_ == DeskewMethod::kConstVelocity) {
    const Eigen::Vector3d guess = previous->twist_lidar.value_or(Eigen::Vector3d::Zero());
    const MotionEstimate motion =
        estimateScanMotion(*previous, scan, inputs_.stamp_is_last_beam, guess, params_);
    if (motion.ok) {
      next.twist_lidar = motion.twist_lidar;
      if (!result.match) result.match = motion.match;
    } else {
      result.warnings.push_back("scan-to-scan motion not estimated: " + motion.reason);
      next.twist_lidar = previous->twist_lidar;  // keep the last known motion
    }
  }
  previous = std::move(next);
  return result;
}

}  // namespace slamprep::algo
