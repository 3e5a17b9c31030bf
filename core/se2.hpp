#pragma once
// SE(2): rigid motion in the plane. T_a_b maps points from frame b into frame a.

#include <Eigen/Core>

namespace slamprep {

/// Wraps an angle to (-pi, pi].
double normalizeAngle(double angle_rad);

/// A planar pose (x, y, yaw). Value type; yaw is kept normalised.
struct SE2 {
  double x = 0.0;
  double y = 0.0;
  double yaw = 0.0;

  SE2() = default;
  SE2(double x_m, double y_m, double yaw_rad);

  static SE2 identity() { return {}; }
  /// From a homogeneous 3x3 matrix [[R, t], [0, 1]].
  static SE2 fromMatrix(const Eigen::Matrix3d& T);
  /// Exponential map of the twist xi = (rho_x, rho_y, theta).
  static SE2 exp(const Eigen::Vector3d& xi);

  /// Logarithm: the twist (rho_x, rho_y, theta) with exp(log(T)) = T.
  Eigen::Vector3d log() const;
  Eigen::Matrix3d matrix() const;
  Eigen::Matrix2d rotation() const;
  Eigen::Vector2d translation() const { return {x, y}; }
  Eigen::Vector3d vector() const { return {x, y, yaw}; }

  SE2 inverse() const;
  SE2 operator*(const SE2& other) const;
  Eigen::Vector2d operator*(const Eigen::Vector2d& p) const;
};

/// T_a_b = T_w_a^-1 * T_w_b: pose of b seen from a.
SE2 between(const SE2& T_w_a, const SE2& T_w_b);

/// Geodesic interpolation T_a * exp(f * log(T_a^-1 T_b)): constant twist from a (f=0) to b (f=1).
SE2 interpolate(const SE2& T_a, const SE2& T_b, double fraction);

}  // namespace slamprep
