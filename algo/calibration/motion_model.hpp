#pragma once
// The exact differential-drive motion model used by every calibration method, templated on the
// scalar so Ceres can differentiate it with Jets. Within one encoder step the wheel rates are
// constant, so the base moves along the exact arc exp((ds, 0, dth)) with
//   ds  = (r_L dphi_L + r_R dphi_R) / 2,    dth = (r_R dphi_R - r_L dphi_L) / b   (docs/design.md)
// and an interval's motion is the product of its steps' arcs: no constant-speed assumption.

#include <cmath>
#include <vector>

#include "core/se2.hpp"

namespace slamprep::algo {

/// One encoder step: the wheels turned by dphi over dt_s at a constant rate.
struct EncoderStep {
  double dt_s = 0.0;            ///< duration of the step
  double dphi_left_rad = 0.0;   ///< left wheel rotation over the step
  double dphi_right_rad = 0.0;  ///< right wheel rotation over the step
};

/// A planar pose with a generic scalar (double or ceres::Jet).
template <typename T>
struct Pose2 {
  T x{0.0};
  T y{0.0};
  T yaw{0.0};
};

/// a * b (poses compose like T_a_b * T_b_c).
template <typename T>
Pose2<T> compose(const Pose2<T>& a, const Pose2<T>& b) {
  using std::cos;
  using std::sin;
  const T c = cos(a.yaw), s = sin(a.yaw);
  return {a.x + c * b.x - s * b.y, a.y + s * b.x + c * b.y, a.yaw + b.yaw};
}

/// a^-1.
template <typename T>
Pose2<T> inverse(const Pose2<T>& a) {
  using std::cos;
  using std::sin;
  const T c = cos(a.yaw), s = sin(a.yaw);
  return {-(c * a.x + s * a.y), s * a.x - c * a.y, -a.yaw};
}

/// sin(t)/t and (1 - cos t)/t, with Taylor series near 0 (error below t^6/5040 for |t| < 1e-3).
template <typename T>
T sincOf(const T& t) {
  using std::abs;
  using std::sin;
  if (abs(t) < 1e-3) return T(1.0) - t * t / 6.0 + t * t * t * t / 120.0;
  return sin(t) / t;
}
template <typename T>
T coscOf(const T& t) {
  using std::abs;
  using std::cos;
  if (abs(t) < 1e-3) return t / 2.0 - t * t * t / 24.0 + t * t * t * t * t / 720.0;
  return (T(1.0) - cos(t)) / t;
}

/// The exact arc exp((ds, 0, dth)): translation ds * (sinc(dth), cosc(dth)), rotation dth.
template <typename T>
Pose2<T> arc(const T& ds, const T& dth) {
  return {ds * sincOf(dth), ds * coscOf(dth), dth};
}

/// Base motion over one step with geometry (r_L, r_R, b); `fraction` of the step is used.
template <typename T>
Pose2<T> stepMotion(const EncoderStep& step, const T& r_L, const T& r_R, const T& b,
                    const T& fraction) {
  const T dl = fraction * step.dphi_left_rad, dr = fraction * step.dphi_right_rad;
  return arc(T(0.5) * (r_L * dl + r_R * dr), (r_R * dr - r_L * dl) / b);
}

/// T_baseStart_baseEnd over all steps: the product of the exact arcs.
template <typename T>
Pose2<T> integrateSteps(const std::vector<EncoderStep>& steps, const T& r_L, const T& r_R,
                        const T& b) {
  Pose2<T> pose;
  for (const EncoderStep& step : steps) pose = compose(pose, stepMotion(step, r_L, r_R, b, T(1.0)));
  return pose;
}

/// T_baseStart_baseEnd when the encoder clock runs `offset_s` behind the lidar clock
/// (t_lidar = t_encoder + offset): the lidar window [0, T] is the encoder window
/// [-offset, T - offset] relative to the first step. Steps are cut at the window edges at constant
/// rate; beyond the recorded steps the first/last step's rate is extrapolated. Exact for
/// offset = 0; the derivative w.r.t. the offset is the wheel rate at the window edges.
template <typename T>
Pose2<T> integrateStepsShifted(const std::vector<EncoderStep>& steps, const T& r_L, const T& r_R,
                               const T& b, const T& offset_s) {
  if (steps.empty()) return {};
  const T lo = -offset_s;  // window start, seconds after the first step begins
  double duration = 0.0;
  for (const EncoderStep& step : steps) duration += step.dt_s;
  const T hi = T(duration) - offset_s;
  Pose2<T> pose;
  if (lo < T(0.0))  // window starts before the first step: extrapolate its rate backwards
    pose = compose(pose, stepMotion(steps.front(), r_L, r_R, b, -lo / steps.front().dt_s));
  double t0 = 0.0;
  for (const EncoderStep& step : steps) {
    const double t1 = t0 + step.dt_s;
    // Ties go to the window edge so that d/d(offset) is the edge rate at offset = 0 as well.
    const T a = lo >= T(t0) ? lo : T(t0);
    const T e = hi <= T(t1) ? hi : T(t1);
    if (e > a) pose = compose(pose, stepMotion(step, r_L, r_R, b, (e - a) / step.dt_s));
    t0 = t1;
  }
  if (hi > T(duration))  // window ends after the last step: extrapolate its rate forwards
    pose = compose(pose,
                   stepMotion(steps.back(), r_L, r_R, b, (hi - T(duration)) / steps.back().dt_s));
  return pose;
}

/// Lidar motion predicted from base motion o and mount l: T_lS_lE = l^-1 * o * l.
template <typename T>
Pose2<T> lidarMotion(const Pose2<T>& o_base, const Pose2<T>& T_base_lidar) {
  return compose(compose(inverse(T_base_lidar), o_base), T_base_lidar);
}

/// SE(2) logarithm (rho_x, rho_y, theta) of a pose whose yaw is near (-pi, pi].
template <typename T>
void logOf(const Pose2<T>& p, T* xi) {
  using std::atan2;
  using std::cos;
  using std::sin;
  const T th = atan2(sin(p.yaw), cos(p.yaw));  // wrap
  const T a = sincOf(th), c = coscOf(th);
  const T det = a * a + c * c;  // V = [[a, -c], [c, a]], V^-1 = [[a, c], [-c, a]] / det
  xi[0] = (a * p.x + c * p.y) / det;
  xi[1] = (-c * p.x + a * p.y) / det;
  xi[2] = th;
}

inline Pose2<double> toPose2(const SE2& T) {
  return {T.x, T.y, T.yaw};
}
inline SE2 toSE2(const Pose2<double>& p) {
  return {p.x, p.y, p.yaw};
}

}  // namespace slamprep::algo
