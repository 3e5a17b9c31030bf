#include "slamprep/eval/formats/stale_odometry.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

#include "slamprep/core/order_statistics.hpp"

namespace slamprep::eval {
namespace {

/// The typical period (median dt) and, per component, the speed percentile over moving steps.
std::array<double, 2> thresholds(const std::vector<double>& t,
                                 const std::vector<std::array<double, 2>>& step,
                                 const std::vector<char>& same, const StaleParams& p) {
  std::vector<double> dt;
  std::array<std::vector<double>, 2> rate;
  for (std::size_t k = 1; k < t.size(); ++k) {
    const double d = t[k] - t[k - 1];
    dt.push_back(d);
    if (same[k] || !(d > 0)) continue;
    for (int c = 0; c < 2; ++c) rate[c].push_back(step[k][c] / d);
  }
  const double period = quantile(dt, 0.5);
  std::array<double, 2> out{};
  for (int c = 0; c < 2; ++c)
    out[c] = std::max(p.floor[c], p.periods * period * quantile(rate[c], p.speed_percentile));
  return out;
}

std::string number(double v) {
  std::ostringstream s;
  s.precision(3);
  s << v;
  return s.str();
}

template <typename Series, typename Keep>
Series keepIf(const Series& in, const std::vector<StaleRun>& runs, Keep push) {
  std::vector<char> drop(in.size(), 0);
  for (const StaleRun& r : runs)
    for (std::size_t k = r.first + 1; k <= r.first + r.repeats; ++k) drop[k] = 1;
  Series out;
  for (std::size_t k = 0; k < in.size(); ++k)
    if (!drop[k]) push(out, k);
  return out;
}

}  // namespace

std::vector<StaleRun> findStaleRuns(const std::vector<double>& t,
                                    const std::vector<std::array<double, 2>>& step,
                                    const std::vector<char>& same, const StaleParams& p,
                                    std::array<double, 2>& threshold, std::size_t& repeated_runs) {
  threshold = thresholds(t, step, same, p);
  repeated_runs = 0;
  std::vector<StaleRun> runs;
  for (std::size_t first = 0; first + 1 < t.size();) {
    std::size_t last = first;
    while (last + 1 < t.size() && same[last + 1]) ++last;
    const std::size_t next = last + 1;
    if (last + 1 - first >= p.min_run) {
      ++repeated_runs;
      // A run at the end of the log has no catch-up step: nothing says it is stale.
      if (next < t.size() && (step[next][0] > threshold[0] || step[next][1] > threshold[1]))
        runs.push_back({first, last - first, t[first], t[next] - t[first], step[next]});
    }
    first = next;
  }
  return runs;
}

std::size_t StaleReport::dropped() const {
  std::size_t n = 0;
  for (const StaleRun& r : runs) n += r.repeats;
  return n;
}

const StaleRun* StaleReport::longest() const {
  const StaleRun* best = nullptr;
  for (const StaleRun& r : runs)
    if (!best || r.span_s > best->span_s) best = &r;
  return best;
}

std::string StaleReport::text() const {
  std::string s = stream + ": ";
  if (runs.empty())
    return s + "none stale (" + std::to_string(repeated_runs) +
           " runs of repeated values, each followed by an ordinary step)";
  const StaleRun& l = *longest();
  s += std::to_string(runs.size()) + " stale runs, " + std::to_string(dropped()) + " of " +
       std::to_string(samples) + " samples dropped (interpolated over); longest " +
       number(l.span_s) + " s from " + std::to_string(l.start_s) + " s (" +
       std::to_string(l.repeats + 1) + " equal samples, then a step of " + number(l.jump[0]) + " " +
       units[0] + ", " +
       number(units[1] == "rad" ? l.jump[1] * 180 / std::numbers::pi : l.jump[1]) + " " +
       (units[1] == "rad" ? "deg" : units[1]) + "; ordinary steps are under " +
       number(threshold[0]) + " " + units[0] + ", " + number(threshold[1]) + " " + units[1] + ")";
  return s;
}

PoseSeries dropStaleOdometry(const PoseSeries& poses, StaleReport& report, const StaleParams& p) {
  const std::size_t n = poses.size();
  std::vector<double> t(n);
  std::vector<std::array<double, 2>> step(n);
  std::vector<char> same(n, 0);
  for (std::size_t k = 0; k < n; ++k) {
    t[k] = poses[k].stamp_s;
    if (k == 0) continue;
    const SE2 &a = poses[k - 1].value, &b = poses[k].value;
    same[k] = a.x == b.x && a.y == b.y && a.yaw == b.yaw;
    step[k] = {std::hypot(b.x - a.x, b.y - a.y),
               std::abs(std::remainder(b.yaw - a.yaw, 2 * std::numbers::pi))};
  }
  report.samples = n;
  report.units = {"m", "rad"};
  report.runs = findStaleRuns(t, step, same, p, report.threshold, report.repeated_runs);
  return keepIf(poses, report.runs,
                [&](PoseSeries& out, std::size_t k) { out.push_back(t[k], poses[k].value); });
}

EncoderLog dropStaleEncoders(const EncoderLog& enc, double rad_per_tick, StaleReport& report,
                             const StaleParams& p) {
  const std::size_t n = enc.size();
  std::vector<double> t(n);
  std::vector<std::array<double, 2>> step(n);
  std::vector<char> same(n, 0);
  for (std::size_t k = 0; k < n; ++k) {
    t[k] = enc[k].stamp_s;
    if (k == 0) continue;
    const EncoderSample &a = enc[k - 1], &b = enc[k];
    same[k] = a.ticks_left == b.ticks_left && a.ticks_right == b.ticks_right;
    step[k] = {std::abs(double(b.ticks_left - a.ticks_left)) * rad_per_tick,
               std::abs(double(b.ticks_right - a.ticks_right)) * rad_per_tick};
  }
  report.samples = n;
  report.units = {"rad (left wheel)", "rad (right wheel)"};
  report.runs = findStaleRuns(t, step, same, p, report.threshold, report.repeated_runs);
  return keepIf(enc, report.runs, [&](EncoderLog& out, std::size_t k) { out.push_back(enc[k]); });
}

}  // namespace slamprep::eval
