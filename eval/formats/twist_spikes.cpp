#include "slamprep/eval/formats/twist_spikes.hpp"

#include <cmath>
#include <numbers>
#include <sstream>

#include "slamprep/core/order_statistics.hpp"

namespace slamprep::eval {
namespace {

std::string number(double v) {
  std::ostringstream s;
  s.precision(4);
  s << v;
  return s.str();
}

/// Spikes of one component: `value[i]` the logged twist, `derived[i]` the poses' velocity.
void findSpikes(const std::vector<double>& stamp, const std::vector<double>& value,
                const std::vector<double>& derived, double absurd, double mad_factor,
                TwistSpikes& out) {
  std::vector<double> r(value.size());
  for (std::size_t i = 0; i < r.size(); ++i) r[i] = value[i] - derived[i];
  const double m = median(r);
  std::vector<double> dev(r.size());
  for (std::size_t i = 0; i < r.size(); ++i) dev[i] = std::abs(r[i] - m);
  out.threshold = mad_factor * 1.4826 * median(dev);  // 1.4826 MAD: sigma of a normal
  for (std::size_t i = 0; i < r.size(); ++i) {
    if (!(dev[i] > out.threshold) || !(std::abs(value[i]) > absurd)) continue;
    ++out.count;
    if (std::abs(value[i]) > std::abs(out.largest)) {
      out.largest = value[i];
      out.largest_at_s = stamp[i];
      out.derived_there = derived[i];
    }
  }
}

std::string spikesText(const TwistSpikes& s, const char* unit) {
  if (s.count == 0) return "no " + s.component + " spikes";
  return std::to_string(s.count) + " " + s.component + " spikes (largest " + number(s.largest) +
         " " + unit + " at " + number(s.largest_at_s) + " s where the poses show " +
         number(s.derived_there) + " " + unit + ")";
}

}  // namespace

TwistSpikeReport findTwistSpikes(std::size_t n,
                                 const std::function<const OdometrySample&(std::size_t)>& at,
                                 const TwistSpikeParams& p) {
  TwistSpikeReport report;
  std::vector<double> stamp, w, w_derived, v, v_derived;
  for (std::size_t k = 1; k + 1 < n; ++k) {
    const OdometrySample &before = at(k - 1), &now = at(k), &after = at(k + 1);
    const double dt = after.stamp_s - before.stamp_s;
    if (!(dt > 0)) continue;
    const SE2 &a = before.pose, &b = after.pose;
    const double heading = now.pose.yaw;
    stamp.push_back(now.stamp_s);
    w.push_back(now.angular_z);
    w_derived.push_back(std::remainder(b.yaw - a.yaw, 2 * std::numbers::pi) / dt);
    v.push_back(now.linear_x);
    v_derived.push_back(((b.x - a.x) * std::cos(heading) + (b.y - a.y) * std::sin(heading)) / dt);
  }
  findSpikes(stamp, w, w_derived, p.absurd_angular, p.mad_factor, report.angular);
  findSpikes(stamp, v, v_derived, p.absurd_linear, p.mad_factor, report.linear);
  return report;
}

std::string TwistSpikeReport::text() const {
  return stream + " twist: " + spikesText(angular, "rad/s") + ", " + spikesText(linear, "m/s");
}

}  // namespace slamprep::eval
