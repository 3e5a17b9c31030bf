#include "slamprep/eval/bench/trajectory_smoother.hpp"

#include <Eigen/Core>
#include <Eigen/LU>
#include <cmath>
#include <numbers>

namespace slamprep::eval {
namespace {

/// Innovations beyond this many sigmas count linearly (Huber): one glitched match neither
/// drags the smoothed motion nor inflates the fitted error of every other pose.
constexpr double kHuberSigmas = 3.0;
constexpr std::size_t kMinPoses = 10;

struct Filtered {
  std::vector<Eigen::Vector2d> s, s_pred;
  std::vector<Eigen::Matrix2d> P, P_pred;
  double neg2_log_likelihood = 0.0;
};

Eigen::Matrix2d transition(double dt) {
  return (Eigen::Matrix2d() << 1.0, dt, 0.0, 1.0).finished();
}

Eigen::Matrix2d processNoise(double q, double dt) {  // Eq. 1
  return q * (Eigen::Matrix2d() << dt * dt * dt / 3.0, dt * dt / 2.0, dt * dt / 2.0, dt).finished();
}

/// The Kalman filter of Eqs. 1-2 from the first position, its velocity unknown (a variance
/// 10^6 times what r per step could explain); Eq. 3 from the third position on, when the first
/// two have fixed position and velocity.
Filtered filter(const std::vector<double>& t, const std::vector<double>& z, double r, double q) {
  const std::size_t n = z.size();
  Filtered f;
  f.s.resize(n), f.s_pred.resize(n), f.P.resize(n), f.P_pred.resize(n);
  const double r2 = r * r;
  const double dt0 = t[1] - t[0];
  f.s[0] = {z[0], 0.0};
  f.P[0] << r2, 0.0, 0.0, 1e6 * r2 / (dt0 * dt0);
  f.s_pred[0] = f.s[0], f.P_pred[0] = f.P[0];
  for (std::size_t k = 1; k < n; ++k) {
    const double dt = t[k] - t[k - 1];
    const Eigen::Matrix2d F = transition(dt);
    f.s_pred[k] = F * f.s[k - 1];
    f.P_pred[k] = F * f.P[k - 1] * F.transpose() + processNoise(q, dt);
    const double nu = z[k] - f.s_pred[k](0);
    const double S = f.P_pred[k](0, 0) + r2;
    const double u = std::abs(nu) / std::sqrt(S);
    // Huber: beyond kHuberSigmas sigmas the match's error variance counts u / c times.
    const double inflate = u > kHuberSigmas ? u / kHuberSigmas : 1.0;
    const double S_used = f.P_pred[k](0, 0) + r2 * inflate;
    const Eigen::Vector2d K = f.P_pred[k].col(0) / S_used;
    f.s[k] = f.s_pred[k] + K * nu;
    f.P[k] = f.P_pred[k] - K * f.P_pred[k].row(0);
    if (k >= 2)
      f.neg2_log_likelihood +=
          std::log(S) + (u > kHuberSigmas ? kHuberSigmas * (2.0 * u - kHuberSigmas) : u * u);
  }
  return f;
}

double neg2LogLikelihood(const std::vector<double>& t, const std::vector<double>& z, double log_r,
                         double log_q) {
  return filter(t, z, std::pow(10.0, log_r), std::pow(10.0, log_q)).neg2_log_likelihood;
}

/// The best (log10 r, log10 q) on a grid of `steps` around a centre, `step` apart.
void gridSearch(const std::vector<double>& t, const std::vector<double>& z, double step, int steps,
                double& log_r, double& log_q, double& best) {
  const double r0 = log_r, q0 = log_q;
  for (int i = -steps; i <= steps; ++i)
    for (int j = -steps; j <= steps; ++j) {
      const double lr = r0 + i * step, lq = q0 + j * step;
      const double v = neg2LogLikelihood(t, z, lr, lq);
      if (v < best) best = v, log_r = lr, log_q = lq;
    }
}

std::vector<double> unwrapped(const PoseSeries& T) {
  std::vector<double> yaw;
  for (std::size_t k = 0; k < T.size(); ++k)
    yaw.push_back(k == 0 ? T[k].value.yaw
                         : yaw.back() + std::remainder(T[k].value.yaw - T[k - 1].value.yaw,
                                                       2.0 * std::numbers::pi));
  return yaw;
}

}  // namespace

AxisNoise fitAxisNoise(const std::vector<double>& t_s, const std::vector<double>& z) {
  // Twelve decades of each in half-decade steps, then finer around the best.
  double log_r = -2.5, log_q = -2.5, best = INFINITY;
  gridSearch(t_s, z, 0.5, 12, log_r, log_q, best);
  gridSearch(t_s, z, 0.1, 5, log_r, log_q, best);
  gridSearch(t_s, z, 0.02, 5, log_r, log_q, best);
  return {std::pow(10.0, log_r), std::pow(10.0, log_q), best};
}

std::vector<double> smoothAxis(const std::vector<double>& t_s, const std::vector<double>& z,
                               const AxisNoise& noise) {
  const Filtered f = filter(t_s, z, noise.measurement, noise.acceleration_psd);
  const std::size_t n = z.size();
  std::vector<Eigen::Vector2d> s(n);
  s[n - 1] = f.s[n - 1];
  for (std::size_t k = n - 1; k-- > 0;) {  // Rauch-Tung-Striebel
    const Eigen::Matrix2d C =
        f.P[k] * transition(t_s[k + 1] - t_s[k]).transpose() * f.P_pred[k + 1].inverse();
    s[k] = f.s[k] + C * (s[k + 1] - f.s_pred[k + 1]);
  }
  std::vector<double> p(n);
  for (std::size_t k = 0; k < n; ++k) p[k] = s[k](0);
  return p;
}

SmoothedTrajectory smoothTrajectory(const PoseSeries& T_world_base) {
  SmoothedTrajectory out;
  out.T_world_base = T_world_base;
  if (T_world_base.size() < kMinPoses) return out;
  std::vector<double> t, x, y;
  for (const auto& s : T_world_base.samples()) {
    t.push_back(s.stamp_s);
    x.push_back(s.value.x);
    y.push_back(s.value.y);
  }
  const std::vector<double> yaw = unwrapped(T_world_base);
  out.x = fitAxisNoise(t, x), out.y = fitAxisNoise(t, y), out.yaw = fitAxisNoise(t, yaw);
  const std::vector<double> xs = smoothAxis(t, x, out.x), ys = smoothAxis(t, y, out.y),
                            yaws = smoothAxis(t, yaw, out.yaw);
  PoseSeries smoothed;
  double sq_m = 0.0, sq_rad = 0.0;
  for (std::size_t k = 0; k < t.size(); ++k) {
    smoothed.push_back(t[k], SE2(xs[k], ys[k], yaws[k]));
    sq_m += (xs[k] - x[k]) * (xs[k] - x[k]) + (ys[k] - y[k]) * (ys[k] - y[k]);
    sq_rad += (yaws[k] - yaw[k]) * (yaws[k] - yaw[k]);
  }
  out.T_world_base = std::move(smoothed);
  out.rms_shift_m = std::sqrt(sq_m / double(t.size()));
  out.rms_shift_deg = std::sqrt(sq_rad / double(t.size())) * 180.0 / std::numbers::pi;
  return out;
}

}  // namespace slamprep::eval
