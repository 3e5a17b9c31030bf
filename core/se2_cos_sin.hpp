#pragma once
// SE(2) in the form the per-beam loops need: the rotation's cosine and sine kept beside the
// translation, so composing and applying a pose costs no trigonometry. The simulator's lidar
// stream and the de-skew kernel advance a pose beam by beam with it; everything else uses SE2.

#include <Eigen/Core>
#include <cmath>

#include "slamprep/core/se2.hpp"

namespace slamprep {

struct SE2CosSin {
  double c = 1.0, s = 0.0, x = 0.0, y = 0.0;
  double yaw = 0.0;  ///< accumulated, not wrapped: se2() wraps it once

  static SE2CosSin from(const SE2& T) {
    return {std::cos(T.yaw), std::sin(T.yaw), T.x, T.y, T.yaw};
  }

  /// SE2::exp of the twist (rho_x, rho_y, theta): translation V(theta) rho (core/se2.hpp).
  static SE2CosSin exp(const Eigen::Vector3d& xi) {
    const double th = xi.z();
    // Beams interpolate within one physics step (|t| ~ 1e-3 rad): Taylor series to t^9 are exact
    // to rounding below 0.05 rad (next term < 1e-19) and spare the sincos of every beam.
    if (std::abs(th) < 0.05) {
      const double t2 = th * th;
      const double a = 1 - t2 / 6 * (1 - t2 / 20 * (1 - t2 / 42 * (1 - t2 / 72)));  // sin(t) / t
      const double b = th / 2 * (1 - t2 / 12 * (1 - t2 / 30 * (1 - t2 / 56)));  // (1 - cos t) / t
      return {1 - th * b, th * a, a * xi.x() - b * xi.y(), b * xi.x() + a * xi.y(), th};
    }
    const double c = std::cos(th), s = std::sin(th);
    return {c, s, s / th * xi.x() - (1 - c) / th * xi.y(), (1 - c) / th * xi.x() + s / th * xi.y(),
            th};
  }

  SE2CosSin operator*(const SE2CosSin& o) const {
    return {c * o.c - s * o.s, s * o.c + c * o.s, x + c * o.x - s * o.y, y + s * o.x + c * o.y,
            yaw + o.yaw};
  }
  Eigen::Vector2d operator*(const Eigen::Vector2d& p) const {
    return {x + c * p.x() - s * p.y(), y + s * p.x() + c * p.y()};
  }
  Eigen::Vector2d rotate(const Eigen::Vector2d& v) const {
    return {c * v.x() - s * v.y(), s * v.x() + c * v.y()};
  }
  SE2CosSin inverse() const { return {c, -s, -(c * x + s * y), s * x - c * y, -yaw}; }
  SE2 se2() const {
    SE2 T;
    T.x = x;
    T.y = y;
    T.yaw = normalizeAngle(yaw);
    return T;
  }
};

}  // namespace slamprep
