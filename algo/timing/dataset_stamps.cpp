#include "slamprep/algo/timing/dataset_stamps.hpp"

#include <algorithm>
#include <cstdio>
#include <functional>

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

// A stream's fitted grid, and how to write a new stamp back into the dataset.
struct Fitted {
  std::string stream;
  std::vector<double> stamps;
  StampGrid grid;
  std::function<void(std::size_t, double)> set;
};

// The host stamps every stream of a log alike: moving some onto their grids while one that has
// no grid keeps its raw stamps would shift them against each other (fr079's laser at 4.7 Hz
// against its irregular ODOM lines), so then every stream keeps its stamps.
bool aStreamHasNoGrid(const std::vector<Fitted>& fitted) {
  return std::any_of(fitted.begin(), fitted.end(), [](const Fitted& f) {
    return !f.grid.applied && f.grid.reason != "regular already";
  });
}

}  // namespace

std::vector<StreamStamps> regularizeStamps(Dataset& d, const StampGridParams& params) {
  std::vector<Fitted> fitted;
  auto fit = [&](std::string stream, std::vector<double> stamps,
                 std::function<void(std::size_t, double)> set) {
    if (stamps.empty()) return;
    StampGrid grid = fitStampGrid(stamps, params);
    fitted.push_back({std::move(stream), std::move(stamps), std::move(grid), std::move(set)});
  };
  fit("encoders", stampsOf(d.encoders),
      [&](std::size_t i, double t) { d.encoders[i].stamp_s = t; });
  PoseSeries moved;
  fit("odometry", stampsOf(d.odom_nominal.samples()),
      [&](std::size_t i, double t) { moved.push_back(t, d.odom_nominal[i].value); });
  fit("imu", stampsOf(d.imu), [&](std::size_t i, double t) { d.imu[i].stamp_s = t; });
  std::vector<double> scan_stamps;
  for (const ScanRecord& r : d.scans) scan_stamps.push_back(r.scan.stamp_s);
  fit("scans", scan_stamps, [&](std::size_t i, double t) { d.scans[i].scan.stamp_s = t; });

  const bool keep_all = aStreamHasNoGrid(fitted);
  std::vector<StreamStamps> out;
  for (Fitted& f : fitted) {
    if (keep_all && f.grid.applied) {
      f.grid.applied = false;
      f.grid.reason = "kept with the other streams: one of them has no constant-rate grid";
    }
    if (f.grid.applied)
      for (std::size_t i = 0; i < f.stamps.size(); ++i) f.set(i, f.grid.stamps[i]);
    out.push_back(report(f.stream, f.stamps.size(), f.grid));
  }
  if (!moved.empty()) d.odom_nominal = std::move(moved);
  if (anyApplied(out))
    for (ScanRecord& r : d.scans)  // the nominal pose at each (moved) scan stamp
      if (r.T_odom_base_nominal)
        r.T_odom_base_nominal = d.odom_nominal.at(r.scan.stamp_s).value_or(*r.T_odom_base_nominal);
  return out;
}

bool anyApplied(const std::vector<StreamStamps>& streams) {
  return std::any_of(streams.begin(), streams.end(),
                     [](const StreamStamps& s) { return s.applied; });
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
