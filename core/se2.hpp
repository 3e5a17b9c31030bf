#pragma once
// SE(2): rigid motion in the plane. T_a_b maps points from frame b into frame a.
//
// One type for every scalar: SE2 (double) everywhere, SE2T<ceres::Jet> inside cost functors.
// Stored as (x, y, yaw) with yaw kept in (-pi, pi]; the twist xi = (rho_x, rho_y, theta) maps to
//   exp(xi) = (V(theta) rho, theta),   V(theta) = [[sinc, -cosc], [cosc, sinc]](theta),
// with sinc(t) = sin(t) / t and cosc(t) = (1 - cos t) / t.

#include <Eigen/Core>
#include <cmath>
#include <numbers>
#include <type_traits>

namespace slamprep {

/// Wraps an angle to (-pi, pi] with std::remainder: exact, so an angle already inside comes back
/// bit for bit.
double normalizeAngle(double angle_rad);

/// The same for a Jet: returned unchanged inside (-pi, pi] like the double version (no rounding,
/// no trigonometry in cost functors), wrapped by atan2(sin, cos) outside; derivative 1.
template <typename Scalar>
requires(!std::is_arithmetic_v<Scalar>) Scalar normalizeAngle(const Scalar& angle_rad) {
  using std::atan2;
  using std::cos;
  using std::sin;
  if (angle_rad > -std::numbers::pi && angle_rad <= std::numbers::pi) return angle_rad;
  const Scalar wrapped = atan2(sin(angle_rad), cos(angle_rad));  // in [-pi, pi]
  return wrapped <= -std::numbers::pi ? wrapped + 2.0 * std::numbers::pi : wrapped;
}

/// Below this |theta| sinc and cosc use their Taylor series: the closed forms lose precision
/// there and divide by zero at 0; the dropped terms are below t^4 / 120 relative.
inline constexpr double kSmallAngleRad = 1e-4;

/// sin(t) / t.
template <typename Scalar>
Scalar sinc(const Scalar& t) {
  using std::abs;
  using std::sin;
  if (abs(t) < kSmallAngleRad) return Scalar(1.0) - t * t / 6.0;
  return sin(t) / t;
}

/// (1 - cos t) / t.
template <typename Scalar>
Scalar cosc(const Scalar& t) {
  using std::abs;
  using std::cos;
  if (abs(t) < kSmallAngleRad) return t / 2.0 - t * t * t / 24.0;
  return (Scalar(1.0) - cos(t)) / t;
}

/// A planar pose (x, y, yaw). Value type; the constructor normalises yaw.
template <typename Scalar>
struct SE2T {
  using Vector2 = Eigen::Matrix<Scalar, 2, 1>;
  using Vector3 = Eigen::Matrix<Scalar, 3, 1>;
  using Matrix2 = Eigen::Matrix<Scalar, 2, 2>;
  using Matrix3 = Eigen::Matrix<Scalar, 3, 3>;

  Scalar x{0.0};
  Scalar y{0.0};
  Scalar yaw{0.0};

  SE2T() = default;
  SE2T(const Scalar& x_m, const Scalar& y_m, const Scalar& yaw_rad)
      : x(x_m), y(y_m), yaw(normalizeAngle(yaw_rad)) {}

  static SE2T identity() { return {}; }

  /// From a homogeneous 3x3 matrix [[R, t], [0, 1]].
  static SE2T fromMatrix(const Matrix3& T) {
    using std::atan2;
    return {T(0, 2), T(1, 2), atan2(T(1, 0), T(0, 0))};
  }

  /// Exponential map of the twist xi = (rho_x, rho_y, theta): (V(theta) rho, theta).
  static SE2T exp(const Vector3& xi) {
    const Scalar a = sinc(xi.z()), b = cosc(xi.z());
    return {a * xi.x() - b * xi.y(), b * xi.x() + a * xi.y(), xi.z()};
  }

  /// Logarithm: the twist (V(yaw)^-1 t, yaw) with exp(log(T)) = T;
  /// V^-1 = [[a, b], [-b, a]] / (a^2 + b^2) with a = sinc(yaw), b = cosc(yaw).
  Vector3 log() const {
    const Scalar a = sinc(yaw), b = cosc(yaw);
    const Scalar inv_det = Scalar(1.0) / (a * a + b * b);
    const Scalar a_n = a * inv_det, b_n = b * inv_det;
    return {a_n * x + b_n * y, a_n * y - b_n * x, yaw};
  }

  Matrix2 rotation() const {
    using std::cos;
    using std::sin;
    const Scalar c = cos(yaw), s = sin(yaw);
    return (Matrix2() << c, -s, s, c).finished();
  }
  Matrix3 matrix() const {
    Matrix3 T = Matrix3::Identity();
    T.template topLeftCorner<2, 2>() = rotation();
    T.template topRightCorner<2, 1>() = translation();
    return T;
  }
  Vector2 translation() const { return {x, y}; }
  Vector3 vector() const { return {x, y, yaw}; }

  /// T_b_a from T_a_b: (-R^T t, -yaw).
  SE2T inverse() const {
    using std::cos;
    using std::sin;
    const Scalar c = cos(yaw), s = sin(yaw);
    return {-(c * x + s * y), s * x - c * y, -yaw};
  }

  /// T_a_c = T_a_b * T_b_c: (R_a_b t_b_c + t_a_b, yaw_a_b + yaw_b_c).
  SE2T operator*(const SE2T& T_b_c) const {
    using std::cos;
    using std::sin;
    const Scalar c = cos(yaw), s = sin(yaw);
    return {c * T_b_c.x - s * T_b_c.y + x, s * T_b_c.x + c * T_b_c.y + y, yaw + T_b_c.yaw};
  }

  /// p_a = T_a_b * p_b.
  Vector2 operator*(const Vector2& p_b) const {
    using std::cos;
    using std::sin;
    const Scalar c = cos(yaw), s = sin(yaw);
    return {c * p_b.x() - s * p_b.y() + x, s * p_b.x() + c * p_b.y() + y};
  }

  /// The same pose in another scalar (double -> Jet with zero derivatives); yaw is not
  /// re-normalised, so the value is carried over exactly.
  template <typename NewScalar>
  SE2T<NewScalar> cast() const {
    SE2T<NewScalar> out;
    out.x = NewScalar(x);
    out.y = NewScalar(y);
    out.yaw = NewScalar(yaw);
    return out;
  }
};

using SE2 = SE2T<double>;

/// T_a_b = T_w_a^-1 * T_w_b: pose of b seen from a.
template <typename Scalar>
SE2T<Scalar> between(const SE2T<Scalar>& T_w_a, const SE2T<Scalar>& T_w_b) {
  return T_w_a.inverse() * T_w_b;
}

/// Geodesic interpolation T_w_a * exp(f * log(T_a_b)): constant twist from a (f=0) to b (f=1).
template <typename Scalar>
SE2T<Scalar> interpolate(const SE2T<Scalar>& T_w_a, const SE2T<Scalar>& T_w_b,
                         const std::type_identity_t<Scalar>& fraction) {
  return T_w_a * SE2T<Scalar>::exp(fraction * between(T_w_a, T_w_b).log());
}

extern template struct SE2T<double>;

}  // namespace slamprep
