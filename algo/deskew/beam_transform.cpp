#include "slamprep/algo/deskew/beam_transform.hpp"

#include <algorithm>
#include <cmath>

#include "slamprep/core/se2_cos_sin.hpp"

namespace slamprep::algo {
namespace {

constexpr std::size_t kReanchorEvery = 64;

/// Knot k to knot k+1: start pose and twist per second.
struct Segment {
  SE2 T_x_start;
  double t_start = 0.0;
  Eigen::Vector3d twist_per_s = Eigen::Vector3d::Zero();

  SE2 at(double t) const { return T_x_start * SE2::exp(twist_per_s * (t - t_start)); }
};

Segment segment(const Trajectory& knots, std::size_t k) {
  const Knot& a = knots[k];
  const Knot& b = knots[k + 1];
  return {a.T, a.stamp_s, between(a.T, b.T).log() / (b.stamp_s - a.stamp_s)};
}

/// Segment index for t: the last k with stamp_k <= t, clamped to [0, size - 2].
std::size_t segmentIndex(const Trajectory& knots, double t) {
  const auto it = std::upper_bound(knots.begin(), knots.end(), t,
                                   [](double s, const Knot& k) { return s < k.stamp_s; });
  const std::size_t i = it == knots.begin() ? 0 : static_cast<std::size_t>(it - knots.begin()) - 1;
  return std::min(i, knots.size() - 2);
}

}  // namespace

Trajectory toTrajectory(const PoseSeries& poses) {
  Trajectory out;
  out.reserve(poses.size());
  for (const auto& p : poses.samples()) out.push_back({p.stamp_s, p.value});
  return out;
}

SE2 poseAt(const Trajectory& trajectory, double t) {
  if (trajectory.size() == 1) return trajectory.front().T;
  return segment(trajectory, segmentIndex(trajectory, t)).at(t);
}

Trajectory relativeTo(const Trajectory& trajectory, double t) {
  const SE2 T_t_x = poseAt(trajectory, t).inverse();
  Trajectory out = trajectory;
  for (Knot& k : out) k.T = T_t_x * k.T;
  return out;
}

void transformBeams(const LaserScan& scan, double first_beam_s, const Trajectory& trajectory,
                    std::vector<std::optional<Eigen::Vector2d>>& out) {
  const std::size_t n = scan.size();
  out.assign(n, std::nullopt);
  if (n == 0 || trajectory.empty()) return;
  const double dt = scan.time_increment_s;
  const double cd = std::cos(scan.angle_increment_rad), sd = std::sin(scan.angle_increment_rad);
  const std::size_t knots = trajectory.size();
  std::size_t k = knots >= 2 ? segmentIndex(trajectory, first_beam_s) : 0;
  Segment seg;
  SE2CosSin T_x_start, T_x_beam = SE2CosSin::from(trajectory.front().T);
  SE2CosSin T_beam_next;  // the increment over one beam
  double ca = 0.0, sa = 0.0;
  bool anchor = true;
  for (std::size_t i = 0; i < n; ++i) {
    const double t = first_beam_s + i * dt;
    if (knots >= 2) {
      const std::size_t k_old = k;
      while (k + 2 < knots && trajectory[k + 1].stamp_s < t) ++k;
      if (k != k_old || i == 0) {
        seg = segment(trajectory, k);
        T_x_start = SE2CosSin::from(seg.T_x_start);
        T_beam_next = SE2CosSin::from(SE2::exp(seg.twist_per_s * dt));
        anchor = true;
      }
    }
    if (anchor || i % kReanchorEvery == 0) {  // exact pose and direction: no drift
      if (knots >= 2)
        T_x_beam = T_x_start * SE2CosSin::from(SE2::exp(seg.twist_per_s * (t - seg.t_start)));
      ca = std::cos(scan.beamAngle(i));
      sa = std::sin(scan.beamAngle(i));
      anchor = false;
    }
    if (scan.valid(i))
      out[i] = T_x_beam * Eigen::Vector2d(scan.ranges_m[i] * ca, scan.ranges_m[i] * sa);
    if (knots >= 2) T_x_beam = T_x_beam * T_beam_next;
    const double c_next = ca * cd - sa * sd;
    sa = sa * cd + ca * sd;
    ca = c_next;
  }
}

}  // namespace slamprep::algo
