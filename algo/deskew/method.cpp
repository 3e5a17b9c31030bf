#include "slamprep/algo/deskew/method.hpp"

#include <algorithm>
#include <sstream>

namespace slamprep::algo {

ScanTimes scanTimes(const LaserScan& scan, bool stamp_is_last_beam, ReferenceTime reference) {
  ScanTimes t;
  t.first_s = firstBeamTime(scan, stamp_is_last_beam);
  t.last_s = t.first_s + (scan.size() - 1) * scan.time_increment_s;
  switch (reference) {
    case ReferenceTime::kFirst:
      t.ref_s = t.first_s;
      break;
    case ReferenceTime::kMiddle:
      t.ref_s = 0.5 * (t.first_s + t.last_s);
      break;
    case ReferenceTime::kLast:
      t.ref_s = t.last_s;
      break;
  }
  return t;
}

void MethodCall::need(bool given, std::string_view what) const {
  if (!given)
    throw Refusal{DeskewRefusal::kMissingInput, std::string(deskewMethodName(method)) + " needs " +
                                                    std::string(what) + ", none was given"};
}

std::string fmt(double x) {
  std::ostringstream s;
  s.precision(6);
  s << std::fixed << x;
  return s.str();
}

Trajectory lidarKnots(const PoseSeries& poses, const SE2& T_base_lidar, const ScanTimes& t,
                      const LaserScan& scan, bool stamp_is_last_beam, double max_gap_s,
                      std::string_view what) {
  if (auto warning = checkBracketing(scan, stamp_is_last_beam, poses, what))
    throw Refusal{DeskewRefusal::kNotBracketed, *warning};
  const auto b0 = poses.bracket(t.first_s), b1 = poses.bracket(t.last_s);
  const std::size_t end = poses.size() == 1 ? 0 : std::min(b1->index + 1, poses.size() - 1);
  Trajectory knots;
  knots.reserve(end - b0->index + 1);
  for (std::size_t k = b0->index; k <= end; ++k) {
    if (k > b0->index && poses[k].stamp_s - poses[k - 1].stamp_s > max_gap_s)
      throw Refusal{
          DeskewRefusal::kSampleGap,
          std::string(what) + " has a gap of " + fmt(poses[k].stamp_s - poses[k - 1].stamp_s) +
              " s at t = " + fmt(poses[k - 1].stamp_s) + " inside the scan (max_sample_gap_s = " +
              fmt(max_gap_s) + "); refused, not interpolated across"};
    knots.push_back({poses[k].stamp_s, poses[k].value * T_base_lidar});
  }
  return knots;
}

Trajectory lidarKnots(const MethodCall& call, const PoseSeries& poses, const SE2& T_base_lidar,
                      std::string_view what) {
  return lidarKnots(poses, T_base_lidar, call.t, call.scan, call.in.stamp_is_last_beam,
                    call.params.max_sample_gap_s, what);
}

Trajectory constantTwistKnots(const Eigen::Vector3d& twist_per_s, const ScanTimes& t) {
  Trajectory knots{{t.first_s, SE2::exp(twist_per_s * (t.first_s - t.ref_s))}};
  if (t.last_s > t.first_s)
    knots.push_back({t.last_s, SE2::exp(twist_per_s * (t.last_s - t.ref_s))});
  return knots;
}

Trajectory identityKnot(double t) {
  return {{t, SE2()}};
}

}  // namespace slamprep::algo
