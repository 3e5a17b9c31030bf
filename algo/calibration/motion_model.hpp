#pragma once
// The exact differential-drive motion model used by every calibration method, templated on the
// scalar so Ceres can differentiate it with Jets. Within one encoder step the wheel rates are
// constant, so the base moves along the exact arc exp((ds, 0, dth)) with
//   ds  = (r_L dphi_L + r_R dphi_R) / 2,    dth = (r_R dphi_R - r_L dphi_L) / b   (docs/design.md)
// and an interval's motion is the product of its steps' arcs: no constant-speed assumption.

#include <cmath>
#include <utility>
#include <vector>

#include "slamprep/core/se2.hpp"

namespace slamprep::algo {

/// One encoder step: the wheels turned by dphi over dt_s at a constant rate.
struct EncoderStep {
  double dt_s = 0.0;            ///< duration of the step
  double dphi_left_rad = 0.0;   ///< left wheel rotation over the step
  double dphi_right_rad = 0.0;  ///< right wheel rotation over the step
};

/// The exact arc exp((ds, 0, dth)): translation ds * (sinc(dth), cosc(dth)), rotation dth.
template <typename T>
SE2T<T> arc(const T& ds, const T& dth) {
  return SE2T<T>::exp({ds, T(0.0), dth});
}

/// Distance ds and turn dth of the base over `fraction` of one step with geometry (r_L, r_R, b).
template <typename T>
std::pair<T, T> stepDistanceAndTurn(const EncoderStep& step, const T& r_L, const T& r_R, const T& b,
                                    const T& fraction) {
  const T dl = fraction * step.dphi_left_rad, dr = fraction * step.dphi_right_rad;
  return {T(0.5) * (r_L * dl + r_R * dr), (r_R * dr - r_L * dl) / b};
}

/// Base motion over one step with geometry (r_L, r_R, b); `fraction` of the step is used.
template <typename T>
SE2T<T> stepMotion(const EncoderStep& step, const T& r_L, const T& r_R, const T& b,
                   const T& fraction) {
  const auto [ds, dth] = stepDistanceAndTurn(step, r_L, r_R, b, fraction);
  return arc(ds, dth);
}

/// The same with a sideslip: the base also moves sideways at v_y = k v w (k in seconds; tyres
/// pushed outwards by the centripetal load in turns), over the step exp((ds, k ds dth / dt, dth)).
template <typename T>
SE2T<T> stepMotionWithSideslip(const EncoderStep& step, const T& r_L, const T& r_R, const T& b,
                               const T& sideslip_s) {
  const auto [ds, dth] = stepDistanceAndTurn(step, r_L, r_R, b, T(1.0));
  return SE2T<T>::exp({ds, sideslip_s * ds * dth / T(step.dt_s), dth});
}

/// T_baseStart_baseEnd over all steps with a sideslip coefficient k (stepMotionWithSideslip).
template <typename T>
SE2T<T> integrateStepsWithSideslip(const std::vector<EncoderStep>& steps, const T& r_L,
                                   const T& r_R, const T& b, const T& sideslip_s) {
  SE2T<T> T_start_end;
  for (const EncoderStep& step : steps)
    T_start_end = T_start_end * stepMotionWithSideslip(step, r_L, r_R, b, sideslip_s);
  return T_start_end;
}

/// T_baseStart_baseEnd over all steps: the product of the exact arcs.
template <typename T>
SE2T<T> integrateSteps(const std::vector<EncoderStep>& steps, const T& r_L, const T& r_R,
                       const T& b) {
  SE2T<T> T_start_end;
  for (const EncoderStep& step : steps)
    T_start_end = T_start_end * stepMotion(step, r_L, r_R, b, T(1.0));
  return T_start_end;
}

/// T_baseStart_baseEnd when the encoder clock runs `offset_s` behind the lidar clock
/// (t_lidar = t_encoder + offset): the lidar window [0, T] is the encoder window
/// [-offset, T - offset] relative to the first step. Steps are cut at the window edges at constant
/// rate; beyond the recorded steps the first/last step's rate is extrapolated. Exact for
/// offset = 0; the derivative w.r.t. the offset is the wheel rate at the window edges.
template <typename T>
SE2T<T> integrateStepsShifted(const std::vector<EncoderStep>& steps, const T& r_L, const T& r_R,
                              const T& b, const T& offset_s) {
  if (steps.empty()) return {};
  const T lo = -offset_s;  // window start, seconds after the first step begins
  double duration = 0.0;
  for (const EncoderStep& step : steps) duration += step.dt_s;
  const T hi = T(duration) - offset_s;
  SE2T<T> T_start_end;
  if (lo < T(0.0))  // window starts before the first step: extrapolate its rate backwards
    T_start_end = T_start_end * stepMotion(steps.front(), r_L, r_R, b, -lo / steps.front().dt_s);
  double t0 = 0.0;
  for (const EncoderStep& step : steps) {
    const double t1 = t0 + step.dt_s;
    // Ties go to the window edge so that d/d(offset) is the edge rate at offset = 0 as well.
    const T a = lo >= T(t0) ? lo : T(t0);
    const T e = hi <= T(t1) ? hi : T(t1);
    if (e > a) T_start_end = T_start_end * stepMotion(step, r_L, r_R, b, (e - a) / step.dt_s);
    t0 = t1;
  }
  if (hi > T(duration))  // window ends after the last step: extrapolate its rate forwards
    T_start_end =
        T_start_end * stepMotion(steps.back(), r_L, r_R, b, (hi - T(duration)) / steps.back().dt_s);
  return T_start_end;
}

/// Lidar motion predicted from the base motion o and the mount l: T_lS_lE = l^-1 * o * l.
template <typename T>
SE2T<T> lidarMotion(const SE2T<T>& T_baseStart_baseEnd, const SE2T<T>& T_base_lidar) {
  return T_base_lidar.inverse() * T_baseStart_baseEnd * T_base_lidar;
}

}  // namespace slamprep::algo
