#include "algo/deskew/sequence.hpp"

namespace slamprep::algo {

DeskewSequence::DeskewSequence(DeskewMethod method, DeskewSequenceParams params)
    : method_(method), params_(std::move(params)) {}

DeskewResult DeskewSequence::next(DeskewInput input) {
  input.previous = previous_ ? &*previous_ : nullptr;
  DeskewResult result;
  if (!previous_ && method_ == DeskewMethod::kVicp) {
    // Nothing to match on the first scan: left as measured, and said so.
    result = deskew(DeskewMethod::kNone, input, params_.deskew);
    result.warnings.push_back("vicp: first scan of the sequence, left as measured");
  } else {
    result = deskew(method_, input, params_.deskew);
  }
  if (!result.ok) {
    previous_.reset();
    return result;
  }
  if (!deskewMethodUsesPreviousScan(method_) && !params_.match_every_scan) return result;
  PreviousScan next;
  next.scan = *input.scan;
  next.stamp_is_last_beam = input.stamp_is_last_beam;
  next.odometry_error_per_s = result.odometry_error_per_s;
  if (result.twist_lidar) {
    next.twist_lidar = result.twist_lidar;
  } else if (previous_ && result.match) {
    next.twist_lidar =
        result.match->T_ref_cur.log() /
        (result.first_beam_s - firstBeamTime(previous_->scan, previous_->stamp_is_last_beam));
  }
  // const-velocity predicts from the previous motion; the motion into this scan is estimated
  // now, for the next one (and for `slamprep match`).
  if (previous_ && !result.twist_lidar &&
      (method_ == DeskewMethod::kConstVelocity || params_.match_every_scan)) {
    const Eigen::Vector3d guess = previous_->twist_lidar.value_or(Eigen::Vector3d::Zero());
    const MotionEstimate motion = estimateScanMotion(
        *previous_, *input.scan, input.stamp_is_last_beam, guess, params_.deskew);
    if (motion.ok) {
      next.twist_lidar = motion.twist_lidar;
      if (!result.match) result.match = motion.match;
    } else {
      result.warnings.push_back("scan-to-scan motion not estimated: " + motion.reason);
      next.twist_lidar = previous_->twist_lidar;  // keep the last known motion
    }
  }
  previous_ = std::move(next);
  return result;
}

}  // namespace slamprep::algo
