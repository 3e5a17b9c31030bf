// The twin's world and scenario files (docs/twin.md): written with fixed precision, so the same
// fit gives the same bytes.
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include "slamprep/eval/bench/twin.hpp"

namespace slamprep::eval {
namespace {

std::string format(const char* fmt, auto... args) {
  char buf[256];
  std::snprintf(buf, sizeof buf, fmt, args...);
  return buf;
}

std::string commentLines(const std::string& text) {
  std::string out = "# ";
  for (char c : text) out += c == '\n' ? std::string("\n# ") : std::string(1, c);
  return out + "\n";
}

}  // namespace

std::string worldYaml(const sim::World& w, const std::string& comment) {
  std::string y = commentLines(comment);
  y += "name: " + w.name + "\n";
  y += format("start: {x: %.4f, y: %.4f, yaw_deg: %.3f}\n", w.T_world_start.x, w.T_world_start.y,
              w.T_world_start.yaw * 180.0 / std::numbers::pi);
  if (!w.walls.empty()) y += "walls:\n";
  for (const sim::Wall& s : w.walls)
    y += format("  - {from: [%.4f, %.4f], to: [%.4f, %.4f], thickness: %.3f, height: %.2f}\n",
                s.from_m.x(), s.from_m.y(), s.to_m.x(), s.to_m.y(), s.thickness_m, s.height_m);
  if (!w.cylinders.empty()) y += "cylinders:\n";
  for (const sim::Cylinder& c : w.cylinders)
    y += format("  - {center: [%.4f, %.4f], radius: %.4f, height: %.2f}\n", c.center_m.x(),
                c.center_m.y(), c.radius_m, c.height_m);
  if (!w.transients.empty()) y += "transients_file: transients.csv\n";
  return y;
}

std::string scenarioYaml(const TrackedDrive& drive, const TrackParams& track,
                         const sim::TrackingParams& tracking, const std::string& comment) {
  std::string y = commentLines(comment);
  y += "name: twin\nsegments:\n";
  y += format("  - type: track\n    kind: wheel_rates\n    period_s: %.6g\n", track.period_s);
  y += format(
      "    closed_loop: true\n    k_x_per_s: %.6g\n    k_y_per_m2: %.6g\n    k_theta_per_m: "
      "%.6g\n    max_wheel_radps: %.6g\n",
      tracking.k_x_per_s, tracking.k_y_per_m2, tracking.k_theta_per_m, track.max_wheel_radps);
  y += "    values:\n";
  for (const Eigen::Vector2d& c : drive.wheel_rates)
    y += format("      - [%.5f, %.5f]\n", c.x(), c.y());
  return y;
}

}  // namespace slamprep::eval
