// Odometry-assisted de-skew (the lecture's slide): the lidar pose of every beam from the wheel
// odometry around the scan, T_X_L(t) = T_odom_base(t) T_base_lidar.
//   linear:    T_odom_base(t_i) interpolated between the two odometry poses bracketing beam i
//              (constant twist between them);
//   quadratic: p_s, p_m, p_e = odometry at the first, middle and last beam; per component of
//              q(tau) = p_s^-1 p(t_s + tau) fit P(tau) = A tau^2 + B tau + C through (0, 0),
//              (tau_e / 2, q_m) and (tau_e, q_e):
//                C = 0,   A = 2 (q_e - 2 q_m) / tau_e^2,   B = (4 q_m - q_e) / tau_e,
//              and approximate it piecewise linearly: sampled at k + 1 evenly spaced times,
//              constant twist in between.
#include <algorithm>

#include "slamprep/algo/deskew/method.hpp"

namespace slamprep::algo {
namespace {

/// T_odom_lidar at the k + 1 sample times of the quadratic P(tau).
Trajectory quadraticKnots(const PoseSeries& odometry, const SE2& T_base_lidar, const ScanTimes& t,
                          int pieces) {
  const double tau_e = t.last_s - t.first_s, t_m = 0.5 * (t.first_s + t.last_s);
  const SE2 p_s = *odometry.at(t.first_s);
  if (tau_e <= 0.0) return {{t.first_s, p_s * T_base_lidar}};  // a single beam
  const Eigen::Vector3d q_m = between(p_s, *odometry.at(t_m)).vector();
  const Eigen::Vector3d q_e = between(p_s, *odometry.at(t.last_s)).vector();
  const Eigen::Vector3d A = 2.0 * (q_e - 2.0 * q_m) / (tau_e * tau_e);
  const Eigen::Vector3d B = (4.0 * q_m - q_e) / tau_e;
  Trajectory knots;
  const int k = std::max(1, pieces);
  for (int j = 0; j <= k; ++j) {
    const double tau = tau_e * j / k;
    const Eigen::Vector3d q = A * tau * tau + B * tau;
    knots.push_back({t.first_s + tau, p_s * SE2(q.x(), q.y(), q.z()) * T_base_lidar});
  }
  return knots;
}

}  // namespace

Trajectory odomLinearKnots(const MethodCall& call) {
  return relativeTo(lidarKnots(call, call.in.odometry, call.in.T_base_lidar, "odometry"),
                    call.t.ref_s);
}

Trajectory odomQuadraticKnots(const MethodCall& call) {
  lidarKnots(call, call.in.odometry, call.in.T_base_lidar, "odometry");  // bracketing and gaps
  return relativeTo(
      quadraticKnots(call.in.odometry, call.in.T_base_lidar, call.t, call.params.quadratic_pieces),
      call.t.ref_s);
}

}  // namespace slamprep::algo
