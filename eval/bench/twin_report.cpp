// What `slamprep twin` prints and draws (docs/twin.md): the fit's summary lines and the
// comparison's figure.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <numbers>

#include "slamprep/eval/bench/twin_compare.hpp"
#include "slamprep/eval/plot/plot.hpp"

namespace slamprep::eval {

namespace {

/// "0.012" or "-" where the fit had too few pieces (null) or the key is absent.
std::string valueOrDash(const nlohmann::ordered_json& j, const char* key, const char* format) {
  if (!j.contains(key) || !j[key].is_number()) return "-";
  char buf[32];
  std::snprintf(buf, sizeof buf, format, j[key].get<double>());
  return buf;
}

/// Where the recording's slip was fitted again with the matches' heading noise held at the
/// twin's own (docs/twin.md "Wheel slip"): what that fit gave the timing.
std::string heldText(const nlohmann::ordered_json& s) {
  if (!s.contains("reference_noise_held") || !s["reference_noise_held"].is_object()) return "";
  const auto& h = s["reference_noise_held"];
  char buf[256];
  std::snprintf(buf, sizeof buf,
                "slip: the matches' heading noise %.1f mrad per piece where the twin's own show "
                "%.1f: held there, the read jitter %.4f s\n",
                1e3 * s["reference_noise_rad"].get<double>(),
                1e3 * h["reference_noise_rad"].get<double>(), h["timing_jitter_s"].get<double>());
  return buf;
}

/// The slips the recording shows and what the twin was given beyond its physics' own.
std::string slipText(const nlohmann::ordered_json& s) {
  const auto pair = [&s](const char* recording, const char* twin, const char* format) {
    return valueOrDash(s, recording, format) + " (twin " + valueOrDash(s, twin, format) + ")";
  };
  return "slip: each wheel " + pair("sigma", "twin_sigma", "%.4f") + ", in turns " +
         pair("turn_sigma", "twin_turn_sigma", "%.4f") + ", both wheels " +
         pair("common_sigma", "twin_common_sigma", "%.4f") + ", read jitter " +
         pair("timing_jitter_s", "twin_read_jitter_s", "%.4f") + " s\n" + heldText(s);
}

}  // namespace

std::string twinText(const nlohmann::ordered_json& j) {
  char buf[512];
  std::string out;
  const auto& w = j["world"];
  std::snprintf(buf, sizeof buf,
                "world: %d walls, %d short walls, %d posts from %d occupied cells (%.1f %% on "
                "walls); %d cut where the robot drove\n",
                w["walls"].get<int>(), w["short_walls"].get<int>(), w["posts"].get<int>(),
                w["occupied_cells"].get<int>(), w["cells_on_walls_percent"].get<double>(),
                w["cut_by_the_path"].get<int>());
  out += buf;
  if (w.contains("transients")) {
    const auto& t = w["transients"];
    std::snprintf(buf, sizeof buf,
                  "transients: %zu of %zu returns no other moment supports (%.1f %%), replayed "
                  "for %.3f s each (transients.csv)\n",
                  t["transient"].get<std::size_t>(), t["returns"].get<std::size_t>(),
                  100.0 * t["fraction"].get<double>(), t["present_s"].get<double>());
    out += buf;
  }
  const auto& d = j["drive"];
  std::snprintf(buf, sizeof buf,
                "drive: %zu wheel-rate knots over %.2f m; kinematic replay %.4f m RMS (max %.4f "
                "m), %.3f deg RMS from the matched trajectory\n",
                d["knots"].get<std::size_t>(), d["distance_m"].get<double>(),
                d["replay_rms_position_m"].get<double>(), d["replay_max_position_m"].get<double>(),
                d["replay_rms_heading_deg"].get<double>());
  out += buf;
  if (d.contains("mode") && d.contains("physics_max_deviation_m")) {
    std::snprintf(buf, sizeof buf,
                  "drive mode: %s (the closed-loop physics at most %.4f m from the replay)\n",
                  d["mode"].get<std::string>().c_str(), d["physics_max_deviation_m"].get<double>());
    out += buf;
  }
  const auto& l = j["lidar"];
  std::snprintf(
      buf, sizeof buf,
      "lidar: %.2f Hz, %.1f beams per scan, %d per revolution, usable range %.2f m, "
      "range noise %.4f m (%.0f %% of its variance fixed in the world), dropout %.3f where the "
      "world has a wall\n",
      l["rate_hz"]["value"].get<double>(), l["beams_per_scan"]["value"]["mean"].get<double>(),
      l["beams_per_revolution"]["value"].get<int>(), l["usable_max_range_m"]["value"].get<double>(),
      l["range_noise_m"]["value"].get<double>(),
      100.0 * l["range_noise_fixed_share"]["value"].get<double>(),
      l["twin_dropout_probability"]["value"].get<double>());
  out += buf;
  if (l.contains("range_bias_by_beam_m") && !l["range_bias_by_beam_m"]["value"].empty()) {
    double sum_sq = 0.0;
    const auto& bias = l["range_bias_by_beam_m"]["value"];
    for (const auto& b : bias) sum_sq += b.get<double>() * b.get<double>();
    std::snprintf(buf, sizeof buf,
                  "lidar range bias by beam: %.1f mm RMS over %zu beams (each beam's mean residual "
                  "repeats between the recording's halves, correlation %.3f)\n",
                  1e3 * std::sqrt(sum_sq / double(bias.size())), bias.size(),
                  l["residual_beam_halves_correlation"]["value"].get<double>());
    out += buf;
  }
  if (l.contains("range_bias_not_given") && l["range_bias_not_given"].is_string())
    out += "lidar range bias by beam: none given: " + l["range_bias_not_given"].get<std::string>() +
           "\n";
  const auto& m = l["mount"]["value"];
  std::snprintf(
      buf, sizeof buf,
      "lidar mount: told x %.1f mm, y %.1f mm, yaw %.2f deg; the twin's x %.1f mm, y %.1f "
      "mm, yaw %.2f deg%s\n",
      m["told"]["x"].get<double>() * 1e3, m["told"]["y"].get<double>() * 1e3,
      m["told"]["yaw"].get<double>() * 180.0 / std::numbers::pi, m["true"]["x"].get<double>() * 1e3,
      m["true"]["y"].get<double>() * 1e3, m["true"]["yaw"].get<double>() * 180.0 / std::numbers::pi,
      m.contains("calibrated") ? " (the calibration's where it departs from the told one)"
                               : " (as told)");
  out += buf;
  const auto& o = j["odometry"];
  const auto& t = o["true"]["value"];
  std::snprintf(buf, sizeof buf,
                "odometry: %.2f Hz, %zu gaps; true geometry r_L %.2f mm, r_R %.2f mm, b %.2f mm "
                "(%s)\n",
                o["rate_hz"]["value"].get<double>(), o["gaps"]["value"]["count"].get<std::size_t>(),
                t["radius_left_m"].get<double>() * 1e3, t["radius_right_m"].get<double>() * 1e3,
                t["wheel_base_m"].get<double>() * 1e3, o["true"]["how"].get<std::string>().c_str());
  out += buf;
  return out + slipText(o["slip"]);
}

namespace {

/// The recording's folder name ("a/b/" and "a/b" both give "b").
std::string recordingName(const std::string& path) {
  const std::filesystem::path p = std::filesystem::path(path).lexically_normal();
  return (p.has_filename() ? p.filename() : p.parent_path().filename()).string();
}

// A statistic's name short enough for a bar's label (by name: the list grows).
std::string shortLabel(const std::string& name) {
  static const std::map<std::string, std::string> shorts = {
      {"scan_rate_hz", "rate"},
      {"beams_per_scan_mean", "beams"},
      {"no_return_fraction", "no ret."},
      {"scan_to_map_residual_median_m", "res. md"},
      {"scan_to_map_residual_p95_m", "res. 95"},
      {"scan_residual_neighbour_correlation", "corr."},
      {"scan_residual_revisit_correlation", "revisit"},
      {"scan_transient_fraction", "trans."},
      {"match_converged_percent", "conv."},
      {"odometry_drift_per_m", "drift"},
      {"odometry_step_noise_deg", "step"},
      {"wheels_vs_scans_residual_deg", "wh/sc"},
      {"calibration_sigma_b", "sd b"},
      {"calibration_b_m", "b"}};
  const auto it = shorts.find(name);
  return it == shorts.end() ? name : it->second;
}

/// Whole decades from 0.1 to 10, widened to hold every ratio: a bar below the axis is not drawn.
plot::Range ratioRange(const std::vector<TwinComparisonRow>& rows) {
  double lo = 0.1, hi = 10.0;
  for (const auto& r : rows)
    if (r.ratio && *r.ratio > 0.0) {
      lo = std::min(lo, std::pow(10.0, std::floor(std::log10(*r.ratio))));
      hi = std::max(hi, std::pow(10.0, std::ceil(std::log10(*r.ratio))));
    }
  return {lo, hi};
}

}  // namespace

void plotComparison(const TwinComparison& c, const std::filesystem::path& png) {
  plot::Figure fig{.width_px = 1800,
                   .height_px = 700,
                   .title = "twin against recording " + recordingName(c.real),
                   .cols = 2};
  plot::Axes ratios{.title = "twin / real (band +-25 %; n/a: no ratio, real value 0 or missing)",
                    .y_label = "twin / real",
                    .log_y = true,
                    .legend = plot::LegendPosition::None};
  plot::Series bars{.label = "twin / real", .style = plot::Style::Bars};
  for (std::size_t i = 0; i < c.rows.size(); ++i) {
    // No bar can mean no ratio (a real value of 0, a side without the statistic): say so.
    const std::string name = shortLabel(c.rows[i].name);
    ratios.categories.push_back(c.rows[i].ratio ? name : "n/a");
    bars.x.push_back(double(i));
    bars.y.push_back(c.rows[i].ratio ? *c.rows[i].ratio : NAN);
  }
  const double right = double(c.rows.size()) - 0.5;
  for (double level : {0.75, 1.0, 1.25})
    ratios.series.push_back({.x = {-0.5, right},
                             .y = {level, level},
                             .color = plot::rgb(0x555555),
                             .line_width_px = 1.5,
                             .dashed = level != 1.0});
  ratios.series.push_back(bars);
  ratios.dodge = false;
  ratios.y_range = ratioRange(c.rows);
  plot::Axes box{.title = "per-scan RMS residual against the map",
                 .y_label = "residual [m]",
                 .legend = plot::LegendPosition::None,
                 .categories = {"real", "twin"}};
  plot::Series a{.x = {}, .y = c.real_residuals_m, .style = plot::Style::Box};
  a.x.assign(c.real_residuals_m.size(), 0.0);
  plot::Series b{.x = {}, .y = c.twin_residuals_m, .style = plot::Style::Box};
  b.x.assign(c.twin_residuals_m.size(), 1.0);
  box.dodge = false;
  box.series = {a, b};
  fig.axes = {ratios, box};
  plot::renderPng(fig, png);
}

}  // namespace slamprep::eval
