#include "core/se2.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <numbers>

namespace slamprep {
namespace {

// sin(t)/t and (1-cos t)/t with Taylor series near zero, where the closed forms lose precision.
double sinc(double t) {
  return std::abs(t) < 1e-4 ? 1.0 - t * t / 6.0 : std::sin(t) / t;
}
double cosc(double t) {
  return std::abs(t) < 1e-4 ? t / 2.0 - t * t * t / 24.0 : (1.0 - std::cos(t)) / t;
}

// V(theta) = [[sinc, -cosc], [cosc, sinc]]: maps the twist's rho to the translation.
Eigen::Matrix2d leftJacobian(double theta) {
  const double a = sinc(theta), b = cosc(theta);
  return (Eigen::Matrix2d() << a, -b, b, a).finished();
}

}  // namespace

double normalizeAngle(double angle_rad) {
  double a = std::remainder(angle_rad, 2.0 * std::numbers::pi);  // in [-pi, pi]
  return a <= -std::numbers::pi ? a + 2.0 * std::numbers::pi : a;
}

SE2::SE2(double x_m, double y_m, double yaw_rad) : x(x_m), y(y_m), yaw(normalizeAngle(yaw_rad)) {}

SE2 SE2::fromMatrix(const Eigen::Matrix3d& T) {
  return {T(0, 2), T(1, 2), std::atan2(T(1, 0), T(0, 0))};
}

SE2 SE2::exp(const Eigen::Vector3d& xi) {
  const Eigen::Vector2d t = leftJacobian(xi.z()) * xi.head<2>();
  return {t.x(), t.y(), xi.z()};
}

Eigen::Vector3d SE2::log() const {
  const Eigen::Vector2d rho = leftJacobian(yaw).inverse() * translation();
  return {rho.x(), rho.y(), yaw};
}

Eigen::Matrix2d SE2::rotation() const {
  const double c = std::cos(yaw), s = std::sin(yaw);
  return (Eigen::Matrix2d() << c, -s, s, c).finished();
}

Eigen::Matrix3d SE2::matrix() const {
  Eigen::Matrix3d T = Eigen::Matrix3d::Identity();
  T.topLeftCorner<2, 2>() = rotation();
  T.topRightCorner<2, 1>() = translation();
  return T;
}

SE2 SE2::inverse() const {
  const Eigen::Vector2d t = -(rotation().transpose() * translation());
  return {t.x(), t.y(), -yaw};
}

SE2 SE2::operator*(const SE2& other) const {
  const Eigen::Vector2d t = rotation() * other.translation() + translation();
  return {t.x(), t.y(), yaw + other.yaw};
}

Eigen::Vector2d SE2::operator*(const Eigen::Vector2d& p) const {
  return rotation() * p + translation();
}

SE2 between(const SE2& T_w_a, const SE2& T_w_b) {
  return T_w_a.inverse() * T_w_b;
}

SE2 interpolate(const SE2& T_a, const SE2& T_b, double fraction) {
  return T_a * SE2::exp(fraction * between(T_a, T_b).log());
}

}  // namespace slamprep
