#include "algo/timing/dataset_stamps.hpp"

#include <algorithm>
#include <cstdio>

namespace slamprep::algo {
namespace {

template <typename Sample>
std::vector<double> stampsOf(const std::vector<Sample>& samples) {
  std::vector<double> t;
  t.reserve(samples.size());
  for (const Sample& s : samples) t.push_back(s.stamp_s);
  return t;
}

StreamStamps report(std::string stream, std::size_t samples, const StampGrid& grid) {
  return {std::move(stream),   samples,
          grid.applied,        grid.reason,
          grid.period_s,       grid.residual_rms_s,
          grid.residual_max_s, grid.missing_samples};
}

// Fits the grid of `stamps` and, when applied, hands each new stamp to set(i, t).
template <typename Set>
StreamStamps regularize(std::string stream, const std::vector<double>& stamps,
                        const StampGridParams& params, Set set) {
  const StampGrid grid = fitStampGrid(stamps, params);
  if (grid.applied)
    for (std::size_t i = 0; i < stamps.size(); ++i) set(i, grid.stamps[i]);
  return report(std::move(stream), stamps.size(), grid);
}

}  // namespace

std::vector<StreamStamps> regularizeStamps(Dataset& d, const StampGridParams& params) {
  std::vector<StreamStamps> out;
  if (!d.encoders.empty())
    out.push_back(regularize("encoders", stampsOf(d.encoders), params,
                             [&](std::size_t i, double t) { d.encoders[i].stamp_s = t; }));
  if (!d.odom_nominal.empty()) {
    PoseSeries moved;
    moved.reserve(d.odom_nominal.size());
    out.push_back(
        regularize("odometry", stampsOf(d.odom_nominal.samples()), params,
                   [&](std::size_t i, double t) { moved.push_back(t, d.odom_nominal[i].value); }));
    if (out.back().applied) d.odom_nominal = std::move(moved);
  }
  if (!d.imu.empty())
    out.push_back(regularize("imu", stampsOf(d.imu), params,
                             [&](std::size_t i, double t) { d.imu[i].stamp_s = t; }));
  if (!d.scans.empty()) {
    std::vector<double> t;
    for (const ScanRecord& r : d.scans) t.push_back(r.scan.stamp_s);
    out.push_back(regularize("scans", t, params, [&](std::size_t i, double stamp) {
      ScanRecord& r = d.scans[i];
      r.scan.stamp_s = stamp;
      if (r.T_odom_base_nominal)
        r.T_odom_base_nominal = d.odom_nominal.at(stamp).value_or(*r.T_odom_base_nominal);
    }));
  }
  return out;
}

bool anyApplied(const std::vector<StreamStamps>& streams) {
  return std::any_of(streams.begin(), streams.end(),
                     [](const StreamStamps& s) { return s.applied; });
}

nlohmann::json stampsJson(const std::vector<StreamStamps>& streams) {
  nlohmann::json out = nlohmann::json::object();
  for (const StreamStamps& s : streams)
    out[s.stream] = {{"applied", s.applied},
                     {"reason", s.reason},
                     {"samples", s.samples},
                     {"period_s", s.period_s},
                     {"residual_rms_s", s.residual_rms_s},
                     {"residual_max_s", s.residual_max_s},
                     {"missing_samples", s.missing_samples}};
  return out;
}

std::string stampsSummary(const std::vector<StreamStamps>& streams) {
  std::string out;
  for (const StreamStamps& s : streams) {
    if (!s.applied) continue;
    char line[200];
    std::snprintf(line, sizeof line,
                  "stamps: %s put on their %.4g s grid (jitter RMS %.3g ms, max %.3g ms)\n",
                  s.stream.c_str(), s.period_s, 1e3 * s.residual_rms_s, 1e3 * s.residual_max_s);
    out += line;
  }
  return out;
}

}  // namespace slamprep::algo
