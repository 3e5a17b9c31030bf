#pragma once
// Closed-loop tracking of a reference path (a `track` segment with closed_loop, docs/simulate.md):
// the feed-forward twist of the reference corrected by the robot's error from the reference pose,
// with the tracking law of Kanayama, Kimura, Miyazaki and Noguchi, "A stable tracking control
// method for an autonomous mobile robot", ICRA 1990.

#include <Eigen/Core>

#include "slamprep/core/se2.hpp"

namespace slamprep::sim {

/// The gains of the tracking law and the cap of its wheel rates. Linearised about the reference,
/// the cross-track error obeys e_y'' + |v_r| k_theta e_y' + v_r^2 k_y e_y = 0: the defaults
/// (k_y = k_theta^2 / 4) damp it critically, with a time constant of 1 / (v_r sqrt(k_y)) = 1 s at
/// 0.5 m/s; the along-track error decays as exp(-k_x t). Gentle on purpose: a robot whose wheel
/// slips cannot take a stiffer correction (on closed_loop_test.cpp's slippery patch k_x 4,
/// k_theta 16, k_y 64 left the replay farther than the open loop did).
struct TrackingParams {
  double k_x_per_s = 1.0;        ///< along-track error to speed (1/s)
  double k_y_per_m2 = 4.0;       ///< cross-track error to turn rate per unit speed (1/m^2)
  double k_theta_per_m = 4.0;    ///< heading error to turn rate per unit speed (1/m)
  double max_wheel_radps = 0.0;  ///< |wheel rate| cap; 0: the segment's largest commanded one
};

/// The twist (v, w) that drives a robot at T_world_base onto T_world_reference, which moves with
/// the reference twist (v_r, w_r). With the error in the robot's frame,
/// (e_x, e_y, e_theta) = T_world_base^-1 T_world_reference:
///   v = v_r cos(e_theta) + k_x e_x                                   // Eq. (1)
///   w = w_r + v_r k_y e_y + |v_r| k_theta sin(e_theta)               // Eq. (2)
/// Kanayama et al. 1990 (stable for v_r > 0 and positive gains) write v_r (k_y e_y + k_theta
/// sin(e_theta)); |v_r| in the heading term keeps it stable when the reference drives backwards
/// (linearised, e_y' = v_r e_theta and e_theta' = -v_r k_y e_y - |v_r| k_theta e_theta: trace
/// -|v_r| k_theta, determinant v_r^2 k_y), where theirs would turn the robot round. At v_r = 0,
/// a turn on the spot, only e_x is corrected.
Eigen::Vector2d trackingTwist(const SE2& T_world_base, const SE2& T_world_reference,
                              const Eigen::Vector2d& reference_twist, const TrackingParams& gains);

/// `rates` scaled down so that neither wheel exceeds `max_radps` (the turn's ratio stays).
Eigen::Vector2d capWheelRates(const Eigen::Vector2d& rates, double max_radps);

}  // namespace slamprep::sim
