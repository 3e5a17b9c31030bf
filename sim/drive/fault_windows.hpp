#pragma once
// When random fault events happen: Poisson start times, and windows of random length for the
// faults that last a while (encoder dropouts, stale odometry, a held robot).

#include <vector>

#include "slamprep/sim/drive/rng.hpp"

namespace slamprep::sim {

/// A stretch [from_s, to_s) of true time.
struct TimeWindow {
  double from_s = 0.0;
  double to_s = 0.0;
  bool contains(double t_s) const { return t_s >= from_s && t_s < to_s; }
};

/// Event times of a Poisson process of `rate_hz` on [0, duration_s): exponential gaps.
std::vector<double> poissonTimes(SplitMix64& rng, double rate_hz, double duration_s);

/// Windows starting at Poisson times (poissonTimes first, then one uniform length in
/// [min_s, max_s] per start, in order, all drawn from `rng`). A window that starts inside the
/// one before it is left out, so the windows are ordered and disjoint.
std::vector<TimeWindow> poissonWindows(SplitMix64& rng, double rate_hz, double min_s, double max_s,
                                       double duration_s);

}  // namespace slamprep::sim
