#pragma once
// Proprioceptive sensors of the simulated robot: wheel encoders and a planar IMU. Each has its
// own rate and its own seeded noise stream (sim/drive/rng.hpp).

#include <Eigen/Core>
#include <cstdint>

#include "slamprep/core/samples.hpp"
#include "slamprep/sim/drive/rng.hpp"

namespace slamprep::sim {

struct EncoderConfig {
  int ticks_per_revolution = 4096;  ///< quantisation: ticks per wheel revolution
  double rate_hz = 100.0;           ///< sampling rate
  /// Random wheel slip: each wheel's encoder counts (1 + s) of what it rolled on the floor, s an
  /// Ornstein-Uhlenbeck process per wheel with this stationary sigma (0: off) ...
  double slip_sigma = 0.0;
  double slip_tau_s = 0.5;  ///< ... and this correlation time (of the turn slip too)
  /// Slip in turns: the wheels count (1 + u) of the turn they made, u an Ornstein-Uhlenbeck
  /// process with this stationary sigma (0: off): in a turn the tyres scrub and the castor
  /// drags, so the turn per wheel angle varies, while straight driving keeps its distance.
  double turn_slip_sigma = 0.0;
  /// Slip both wheels share: they count (1 + c) of the distance rolled, c an Ornstein-Uhlenbeck
  /// process with this stationary sigma (0: off): the distance varies, the turn does not.
  double common_slip_sigma = 0.0;
};

struct ImuConfig {
  double rate_hz = 200.0;            ///< sampling rate
  double gyro_noise_radps = 0.002;   ///< white noise sigma per sample
  double gyro_bias_radps = 0.001;    ///< constant bias added to every sample
  double accel_noise_mps2 = 0.02;    ///< white noise sigma per sample and axis
  double accel_bias_x_mps2 = 0.02;   ///< constant bias, base x
  double accel_bias_y_mps2 = -0.01;  ///< constant bias, base y
};

/// Cumulative ticks of a wheel turned by wheel_angle_rad since start: an incremental encoder
/// counts whole ticks, so ticks = floor(angle / (2 pi / N)) (also for negative angles).
std::int64_t quantizeTicks(double wheel_angle_rad, int ticks_per_revolution);

/// Random wheel slip (EncoderConfig::slip_sigma): the encoders count (1 + s_i(t)) of each
/// wheel's turning, s_i an Ornstein-Uhlenbeck process, exact over any step dt:
///   s_k = a s_{k-1} + sigma sqrt(1 - a^2) n_k,  a = exp(-dt / tau),  n_k ~ N(0, 1).
/// Over a window of duration T >> tau the counted angle is off by N(0, 2 sigma^2 tau int w^2 dt).
/// Slip in turns (turn_slip_sigma): u, a third such process, adds u d to the right wheel and
/// takes it from the left, d = (dphi_R - dphi_L) / 2 the step's turning part, so the counted
/// turn is (1 + u) of the turn made and the distance is unchanged. Common slip
/// (common_slip_sigma): c, a fourth, adds c m to both wheels, m = (dphi_L + dphi_R) / 2 the
/// step's straight part, so the counted distance is (1 + c) of the distance rolled and the turn
/// is unchanged.
class WheelSlip {
 public:
  WheelSlip(double sigma, double tau_s, std::uint64_t seed, double turn_sigma = 0.0,
            double common_sigma = 0.0)
      : sigma_(sigma),
        turn_sigma_(turn_sigma),
        common_sigma_(common_sigma),
        tau_s_(tau_s),
        rng_(seed) {}
  bool on() const { return sigma_ > 0.0 || turn_sigma_ > 0.0 || common_sigma_ > 0.0; }
  /// The counted angles after the wheels turned by `turned_rad` over `dt_s`.
  Eigen::Vector2d count(const Eigen::Vector2d& turned_rad, double dt_s);

 private:
  double sigma_, turn_sigma_, common_sigma_, tau_s_;
  SplitMix64 rng_;
  Eigen::Vector2d s_ = Eigen::Vector2d::Zero();  ///< (left, right); starts at 0: no slip at rest
  double u_ = 0.0;                               ///< the turn's
  double c_ = 0.0;                               ///< both wheels'
  Eigen::Vector2d counted_rad_ = Eigen::Vector2d::Zero();
};

/// Sample times k / rate_hz (k = 0, 1, ...), computed by division so they never drift.
class SampleClock {
 public:
  explicit SampleClock(double rate_hz) : rate_hz_(rate_hz) {}
  double next_s() const { return static_cast<double>(k_) / rate_hz_; }
  void advance() { ++k_; }

 private:
  double rate_hz_;
  std::int64_t k_ = 0;
};

/// Planar IMU at the base origin: gyro z and the horizontal specific force in the base frame,
/// each with a constant bias and white Gaussian noise from its own seeded stream.
class Imu {
 public:
  Imu(const ImuConfig& config, std::uint64_t seed) : config_(config), rng_(seed) {}

  ImuSample sample(double stamp_s, double yaw_rate_radps, const Eigen::Vector2d& accel_base_mps2);

 private:
  ImuConfig config_;
  SplitMix64 rng_;
};

}  // namespace slamprep::sim
