#include "slamprep/algo/timing/dataset_stamps.hpp"

#include <algorithm>
#include <cstdio>
#include <functional>
#include <optional>

#include "slamprep/algo/timing/stamp_checks.hpp"

namespace slamprep::algo {
namespace {

template <typename Sample>
std::vector<double> stampsOf(const std::vector<Sample>& samples) {
  std::vector<double> t;
  t.reserve(samples.size());
  for (const Sample& s : samples) t.push_back(s.stamp_s);
  return t;
}

// A stream's fitted grid, how to write a new stamp back into the dataset, and why its stamps
// are right where its own evidence says so ("": no such evidence).
struct Fitted {
  std::string stream;
  std::vector<double> stamps;
  StampGrid grid;
  std::function<void(std::size_t, double)> set;
  std::string right;
};

StreamStamps report(const Fitted& f) {
  const StampGrid& g = f.grid;
  return {f.stream,         f.stamps.size(),  g.applied,         g.reason,        g.period_s,
          g.residual_rms_s, g.residual_max_s, g.missing_samples, !f.right.empty()};
}

// The host stamps every stream of a log alike: moving some onto their grids while one that has
// no grid keeps its raw stamps would shift them against each other (fr079's laser at 4.7 Hz
// against its irregular ODOM lines), so then every stream keeps its stamps. A stream stamped
// right has a grid; it keeps its stamps because they are right.
bool aStreamHasNoGrid(const std::vector<Fitted>& fitted) {
  return std::any_of(fitted.begin(), fitted.end(), [](const Fitted& f) {
    return !f.grid.applied && f.right.empty() && f.grid.reason != "regular already";
  });
}

std::string ms(double s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2g ms", 1e3 * s);
  return buf;
}

/// Why the encoders' stamps are right: their ticks bound the stamp error (Eq. 1 of
/// stamp_checks.hpp) well below their irregularity about the grid.
std::string encodersRight(const Dataset& d, const StampGrid& grid, const StampGridParams& p) {
  if (!grid.applied) return "";
  const std::optional<double> bound = tickStampErrorBound(d.encoders);
  if (!bound || !(*bound < p.right_fraction * grid.residual_rms_s)) return "";
  return "stamped right: their ticks bound the stamp error to " + ms(*bound) + ", their " +
         ms(grid.residual_rms_s) + " about the grid is when they were sampled";
}

}  // namespace

std::vector<StreamStamps> regularizeStamps(Dataset& d, const StampGridParams& params) {
  std::vector<Fitted> fitted;
  auto fit = [&](std::string stream, std::vector<double> stamps,
                 std::function<void(std::size_t, double)> set) {
    if (stamps.empty()) return;
    StampGrid grid = fitStampGrid(stamps, params);
    fitted.push_back({std::move(stream), std::move(stamps), std::move(grid), std::move(set), ""});
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

  // The odometry poses stamped with the encoders (the same stamps) share the encoders' verdict.
  const Fitted* encoders = nullptr;
  for (Fitted& f : fitted) {
    if (f.stream == "encoders") {
      f.right = encodersRight(d, f.grid, params);
      encoders = &f;
    }
    if (f.stream == "odometry" && encoders && f.grid.applied && f.stamps == encoders->stamps)
      f.right = encoders->right;
  }
  const bool keep_all = aStreamHasNoGrid(fitted);
  std::vector<StreamStamps> out;
  for (Fitted& f : fitted) {
    if (!f.right.empty()) {
      f.grid.applied = false;
      f.grid.reason = f.right;
    } else if (keep_all && f.grid.applied) {
      f.grid.applied = false;
      f.grid.reason = "kept with the other streams: one of them has no constant-rate grid";
    }
    if (f.grid.applied)
      for (std::size_t i = 0; i < f.stamps.size(); ++i) f.set(i, f.grid.stamps[i]);
    out.push_back(report(f));
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
    if (s.stamped_right) out += "stamps: " + s.stream + " kept as " + s.reason + "\n";
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
