#pragma once
// The motion behind a matched trajectory (docs/twin.md "Drive"): the matched poses are the
// robot's motion plus each match's error, white from scan to scan; a twin that drives them as
// they are turns centimetres of matching jitter into a jerking robot. Each coordinate (x, y,
// unwrapped yaw) is smoothed by a constant-velocity Rauch-Tung-Striebel smoother:
//   state s = (p, v),  s_k = F s_{k-1} + w,  F = [1 dt; 0 1],
//   Q = q [dt^3/3 dt^2/2; dt^2/2 dt]   (white acceleration of spectral density q),    (Eq. 1)
//   z_k = p_k + e,  e ~ N(0, r^2)      (the match's error),                           (Eq. 2)
// with q and r fitted per coordinate by maximum likelihood of the Kalman filter's innovations
//   -2 log L = sum_k log S_k + nu_k^2 / S_k,                                           (Eq. 3)
// so neither noise is chosen: white error and a smooth motion have different spectra, and a
// recording's few hundred scans tell them apart.

#include <vector>

#include "slamprep/core/time_series.hpp"

namespace slamprep::eval {

/// One coordinate's fitted noises (Eqs. 1-2).
struct AxisNoise {
  double measurement = 0.0;       ///< r: m (or rad), per pose
  double acceleration_psd = 0.0;  ///< q: (m/s^2)^2 / Hz (or rad)
  double neg2_log_likelihood = 0.0;
};

/// The fit of Eq. 3 on one coordinate sampled at increasing stamps.
AxisNoise fitAxisNoise(const std::vector<double>& t_s, const std::vector<double>& z);

/// The RTS smoother's positions at the stamps.
std::vector<double> smoothAxis(const std::vector<double>& t_s, const std::vector<double>& z,
                               const AxisNoise& noise);

struct SmoothedTrajectory {
  PoseSeries T_world_base;  ///< at the input's stamps
  AxisNoise x, y, yaw;
  double rms_shift_m = 0.0;  ///< smoothed against input
  double rms_shift_deg = 0.0;
};

/// Each coordinate fitted and smoothed; fewer than 10 poses are returned as they are.
SmoothedTrajectory smoothTrajectory(const PoseSeries& T_world_base);

}  // namespace slamprep::eval
