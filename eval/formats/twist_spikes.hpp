#pragma once
// Odometry twist samples that no motion explains: twist.angular.z or twist.linear.x far from the
// velocity the poses themselves show around the sample, and physically absurd for a ground robot.
// Reported, not corrected (the dataset keeps poses, not twists). The rule (docs/export.md):
// residual r_k = twist_k - (pose_{k+1} (-) pose_{k-1}) / (t_{k+1} - t_{k-1}) (the forward speed:
// the displacement along the heading at k; the yaw rate: the wrapped yaw change); a spike has
// |r_k - median(r)| > 10 * 1.4826 * MAD(r) and |twist_k| > 10 rad/s (angular) or 5 m/s (linear).

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "slamprep/core/se2.hpp"

namespace slamprep::eval {

/// One Odometry message's pose and twist (in child_frame_id).
struct OdometrySample {
  double stamp_s = 0.0;
  SE2 pose;
  double linear_x = 0.0;   ///< m/s
  double angular_z = 0.0;  ///< rad/s
};

struct TwistSpikeParams {
  double mad_factor = 10.0;      ///< robust sigmas away from the median residual
  double absurd_angular = 10.0;  ///< rad/s
  double absurd_linear = 5.0;    ///< m/s
};

struct TwistSpikes {
  std::string component;  ///< "angular.z" or "linear.x"
  std::size_t count = 0;
  double threshold = 0.0;  ///< the residual bound: 10 * 1.4826 * MAD
  double largest = 0.0;    ///< the largest spike's twist value
  double largest_at_s = 0.0;
  double derived_there = 0.0;  ///< what the poses show at it
};

struct TwistSpikeReport {
  std::string stream;
  TwistSpikes angular{"angular.z"}, linear{"linear.x"};
  std::string text() const;  ///< one line for the import summary
};

/// `at(k)` is sample k of `n`, in stamp order (a deque or a vector: nothing is copied).
TwistSpikeReport findTwistSpikes(std::size_t n,
                                 const std::function<const OdometrySample&(std::size_t)>& at,
                                 const TwistSpikeParams& params = {});

}  // namespace slamprep::eval
