#include "slamprep/sim/drive/fault_windows.hpp"

#include <cmath>

namespace slamprep::sim {

std::vector<double> poissonTimes(SplitMix64& rng, double rate_hz, double duration_s) {
  std::vector<double> times;
  if (!(rate_hz > 0.0)) return times;
  for (double t = 0.0;;) {
    t += -std::log(1.0 - rng.uniform()) / rate_hz;  // 1 - u in (0, 1]: finite log
    if (t >= duration_s) return times;
    times.push_back(t);
  }
}

std::vector<TimeWindow> poissonWindows(SplitMix64& rng, double rate_hz, double min_s, double max_s,
                                       double duration_s) {
  std::vector<TimeWindow> windows;
  for (const double t : poissonTimes(rng, rate_hz, duration_s)) {
    const double length_s = min_s + (max_s - min_s) * rng.uniform();  // drawn for every start
    if (!windows.empty() && t < windows.back().to_s) continue;
    windows.push_back({t, t + length_s});
  }
  return windows;
}

}  // namespace slamprep::sim
