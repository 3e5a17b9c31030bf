#include "slamprep/eval/bench/twin_compare.hpp"

#include <cmath>
#include <cstdio>
#include <map>
#include <numbers>

#include "slamprep/eval/bench/twin_lidar.hpp"
#include "slamprep/eval/bench/twin_odometry.hpp"
#include "slamprep/eval/formats/dataset_io.hpp"
#include "slamprep/eval/metrics/error_stats.hpp"
#include "slamprep/eval/metrics/trajectory_error.hpp"
#include "slamprep/eval/pipeline/calibration_run.hpp"
#include "slamprep/eval/pipeline/match_trajectory.hpp"
#include "slamprep/eval/plot/plot.hpp"

namespace slamprep::eval {
namespace {

const std::map<std::string, const char*>& definitions() {
  static const std::map<std::string, const char*> d = {
      {"scan_rate_hz",
       "1 / the scan stamps' period: their grid's where they have one, else the median step"},
      {"beams_per_scan_mean", "beams per scan, mean over the scans"},
      {"no_return_fraction", "beams without a valid range, of all beams"},
      {"scan_to_map_residual_median_m",
       "slamprep match --deskew none: median over the accepted scans of their RMS point-to-line "
       "residual"},
      {"scan_to_map_residual_p95_m", "the same, 95th percentile"},
      {"scan_residual_neighbour_correlation",
       "slamprep match --deskew vicp: robust correlation of neighbouring beams' range residuals "
       "against the walls of the dataset's own matched map (what the twin's "
       "lidar.range_noise_correlation is tuned to)"},
      {"scan_residual_revisit_correlation",
       "the same residuals' robust correlation where consecutive scans' beams hit within 2 cm of "
       "one another: how much of the range error is fixed in the world (surfaces, clutter: seen "
       "again by the next scan) rather than drawn afresh each scan (a lidar's own noise, which a "
       "matcher mistakes for motion between two scans); the twin's noise is drawn afresh"},
      {"scan_transient_fraction",
       "the returns of those scans, placed by the same matched poses (0.5 m to the usable "
       "range), that no return at least 3 s earlier or later supports within 5 cm, of all: "
       "people walking by, things moved, clutter seen once (docs/twin.md \"Transient "
       "returns\"); the twin's world is still"},
      {"match_converged_percent",
       "slamprep match --deskew none: accepted of all scans but the first"},
      {"odometry_drift_per_m",
       "the raw odometry against the matched trajectory: mean translation error of 1 m pieces of "
       "path (RPE, metres), per metre"},
      {"odometry_step_noise_deg",
       "slamprep match --deskew none: the odometry's heading noise per scan step it measured and "
       "fused with (docs/matching.md \"Odometry noise\"), in degrees; where the 5 s windows "
       "of wheels_vs_scans agree and this does not, the odometry errs on another time scale"},
      {"wheels_vs_scans_residual_deg",
       "the sensor agreement of that calibration (docs/calibration.md): robust sigma, in "
       "degrees, of what the wheels and the scan-matched motion disagree on per 5 s window "
       "after the best wheel-geometry fit and delay (slip, lifted wheels, matcher noise)"},
      {"calibration_sigma_b",
       "1-sigma of b in metres from calibrate --method joint --motion map --keyframe-cm 20 "
       "(null: refused)"},
      {"calibration_b_m",
       "b from the same calibration: its spread over twin seeds against its spread over "
       "recordings is the suite's (scripts/twins.sh)"}};
  return d;
}

std::optional<double> driftPerMetre(const Dataset& d, const MatchTrajectory& run) {
  RpeParams p;
  p.delta = 1.0;
  p.unit = DeltaUnit::kMeters;
  p.pairs_from_reference = true;
  p.max_time_difference_s = 0.1;
  PoseSeries odom;
  for (std::size_t k = 0; k < run.T_world_base.size(); ++k)
    if (const auto T = d.odom_nominal.at(run.T_world_base[k].stamp_s))
      odom.push_back(run.T_world_base[k].stamp_s, *T);
  const RpeResult r = relativePoseError(odom, run.T_world_base, p);
  if (!r.ok) return std::nullopt;
  return r.translation_m.mean;  // pieces of 1 m: metres per metre
}

std::optional<double> stepNoiseDeg(const std::optional<algo::OdometryNoise>& noise) {
  if (!noise) return std::nullopt;
  return noise->sigma_rad * 180.0 / std::numbers::pi;
}

/// What the twin's calibration measures: the joint b and its 1-sigma (nullopt when refused),
/// and how far the wheels and the scans disagree per window.
struct CalibrationFigures {
  std::optional<double> b_m, sigma_b_m, wheels_vs_scans_deg;
};

CalibrationFigures calibrationFigures(const std::string& dir, const Dataset& d) {
  const DatasetCalibration cal = calibrateForTwin(dir, d);
  CalibrationFigures out;
  if (cal.agreement)
    if (const algo::PairAgreement* p = cal.agreement->pair("wheels", "scans"))
      out.wheels_vs_scans_deg = p->sigma_rad * 180.0 / std::numbers::pi;
  if (cal.runs.empty() || !cal.runs.front().result.ok) return out;
  const algo::CalibrationResult& r = cal.runs.front().result;
  out.b_m = r.geometry.wheel_base_m;
  out.sigma_b_m = r.sigma()(2);
  return out;
}

}  // namespace

TwinStatistics measureTwinStatistics(const std::string& dir, bool use_imu) {
  Dataset d = readDataset(dir);
  if (!use_imu) d.imu.clear();
  const LidarLayout l = fitLidarLayout(d);
  TwinStatistics s;
  s.has_imu = !d.imu.empty();
  const ScanPoints points = matchScanPoints(d, "none", false);
  const MatchTrajectory run = matchTrajectory(d, points, twinMatchOptions());
  // What `match` (its default, --odometry-noise measured) finds the odometry's noise per step.
  const auto step_noise = measuredOdometryNoise(d, points);
  for (std::size_t k = 1; k < run.tracked.scans.size(); ++k)
    if (!run.tracked.scans[k].fallback)
      s.residuals_m.push_back(run.tracked.scans[k].match.rms_residual_m);
  const ErrorStats r = summarize(s.residuals_m);
  const double attempted = double(run.tracked.scans.size()) - 1.0;
  const CalibrationFigures cal = calibrationFigures(dir, d);
  const ResidualCorrelations correlations =
      ownMapCorrelations(d, l, {}, {}, /*count_transients=*/true);
  auto opt = [](bool ok, double v) { return ok ? std::optional<double>(v) : std::nullopt; };
  s.values = {
      {"scan_rate_hz", l.rate_hz},
      {"beams_per_scan_mean", l.beams_per_scan_mean},
      {"no_return_fraction", l.no_return_fraction},
      {"scan_to_map_residual_median_m", opt(r.ok, r.median)},
      {"scan_to_map_residual_p95_m", opt(r.ok, r.p95)},
      {"scan_residual_neighbour_correlation", correlations.neighbour},
      {"scan_residual_revisit_correlation", correlations.revisit},
      {"scan_transient_fraction", correlations.transient},
      {"match_converged_percent", opt(attempted > 0, 100.0 * run.tracked.matched / attempted)},
      {"odometry_drift_per_m", driftPerMetre(d, run)},
      {"odometry_step_noise_deg", stepNoiseDeg(step_noise)},
      {"wheels_vs_scans_residual_deg", cal.wheels_vs_scans_deg},
      {"calibration_sigma_b", cal.sigma_b_m},
      {"calibration_b_m", cal.b_m}};
  return s;
}

TwinComparison compareTwin(const std::string& real, const std::string& twin) {
  TwinComparison c{real, twin, {}, {}, {}};
  const TwinStatistics a = measureTwinStatistics(real);
  const TwinStatistics b = measureTwinStatistics(twin, a.has_imu);
  for (std::size_t i = 0; i < a.values.size(); ++i) {
    TwinComparisonRow row{a.values[i].first, a.values[i].second, b.values[i].second, {}};
    if (row.real && row.twin && *row.real != 0.0) row.ratio = *row.twin / *row.real;
    c.rows.push_back(row);
  }
  c.real_residuals_m = a.residuals_m;
  c.twin_residuals_m = b.residuals_m;
  return c;
}

const char* statisticDefinition(const std::string& name) {
  const auto it = definitions().find(name);
  return it == definitions().end() ? "" : it->second;
}

nlohmann::ordered_json comparisonJson(const TwinComparison& c) {
  auto value = [](const std::optional<double>& v) {
    return v ? nlohmann::ordered_json(*v) : nlohmann::ordered_json(nullptr);
  };
  nlohmann::ordered_json stats = nlohmann::ordered_json::object();
  for (const TwinComparisonRow& r : c.rows)
    stats[r.name] = {{"real", value(r.real)},
                     {"twin", value(r.twin)},
                     {"ratio", value(r.ratio)},
                     {"how", statisticDefinition(r.name)}};
  return {{"real", c.real}, {"twin", c.twin}, {"statistics", stats}};
}

std::string comparisonText(const TwinComparison& c) {
  std::string out = "statistic                          real          twin          ratio\n";
  char line[200];
  auto cell = [](const std::optional<double>& v) {
    if (!v) return std::string("-            ");
    char b[32];
    std::snprintf(b, sizeof b, "%-13.5g", *v);
    return std::string(b);
  };
  for (const TwinComparisonRow& r : c.rows) {
    std::snprintf(line, sizeof line, "%-34s %s %s %s\n", r.name.c_str(), cell(r.real).c_str(),
                  cell(r.twin).c_str(), cell(r.ratio).c_str());
    out += line;
  }
  return out;
}

}  // namespace slamprep::eval
