// `slamprep match`: lidar odometry of a dataset by scan-to-local-map matching (point-to-line ICP,
// the odometry as the guess), its trajectory as TUM, one JSON line per scan and a JSON summary
// (docs/matching.md).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <limits>
#include <nlohmann/json.hpp>
#include <numbers>

#include "slamprep/algo/agreement/agreement_report.hpp"
#include "slamprep/algo/agreement/dataset_sources.hpp"
#include "slamprep/algo/deskew/deskew.hpp"
#include "slamprep/app/choices.hpp"
#include "slamprep/app/command_progress.hpp"
#include "slamprep/app/commands.hpp"
#include "slamprep/app/common_flags.hpp"
#include "slamprep/app/exit_codes.hpp"
#include "slamprep/app/icp_options.hpp"
#include "slamprep/app/outputs.hpp"
#include "slamprep/core/atomic_file.hpp"
#include "slamprep/core/error.hpp"
#include "slamprep/eval/formats/dataset_io.hpp"
#include "slamprep/eval/formats/tum.hpp"
#include "slamprep/eval/metrics/error_stats.hpp"
#include "slamprep/eval/pipeline/calibration_run.hpp"
#include "slamprep/eval/pipeline/dataset_deskew.hpp"
#include "slamprep/eval/pipeline/match_trajectory.hpp"

namespace slamprep::app {
namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

struct MatchFlags : CommonFlags {
  std::string dataset;
  std::string out;  // nothing is written without an output flag
  std::string trajectory;
  std::string deskew = "vicp";
  algo::KeyframeOdometryParams params;
  double keyframe_angle_deg = params.keyframe_angle_rad * kDegPerRad;
  double odometry_sigma_deg = params.odometry_sigma_rad * kDegPerRad;
  bool stamp_is_last_beam = false;
  std::string sync = "none";                // --sync
  std::string odometry_noise = "measured";  // --odometry-noise
};

/// The point-to-line RMS residual of the accepted matches (docs/matching.md): how well the
/// scans fit the map they were matched to, what de-skew lowers where the robot turns.
eval::ErrorStats acceptedResiduals(const algo::KeyframeOdometry& t) {
  std::vector<double> rms;
  for (std::size_t k = 1; k < t.scans.size(); ++k)
    if (!t.scans[k].fallback) rms.push_back(t.scans[k].match.rms_residual_m);
  return eval::summarize(std::move(rms));
}

/// The median count of a scan's points within the matcher's range: what ICP has to work with.
std::size_t pointsPerScanMedian(const algo::KeyframeOdometry& t) {
  std::vector<std::size_t> n;
  for (const algo::TrackedScan& s : t.scans) n.push_back(s.points);
  if (n.empty()) return 0;
  std::nth_element(n.begin(), n.begin() + n.size() / 2, n.end());
  return n[n.size() / 2];
}

/// Fallbacks that are none of rejected, unsupported or sparse: no guess's match converged.
std::size_t notConverged(const algo::KeyframeOdometry& t) {
  return t.fallbacks - t.rejected - t.unsupported - t.sparse;
}

/// Which guess each scan's pose came from, and how often the guesses disagreed.
nlohmann::ordered_json hypothesesJson(const eval::MatchTrajectory& run) {
  const algo::KeyframeOdometry& t = run.tracked;
  nlohmann::ordered_json won = nlohmann::ordered_json::object();
  for (const auto& [source, name] : algo::kGuessSourceNames)
    won[std::string(name)] = t.won_by[static_cast<std::size_t>(source)];
  return {{"odometry_guesses", run.odometry_guesses},
          {"gyro_guesses", run.gyro_guesses},
          {"multi_hypothesis", t.multi_hypothesis},
          {"won_by", won}};
}

/// One match of the dataset's scans (de-skewed first), with the sensor agreement against the
/// accepted poses.
struct MatchPass {
  eval::MatchTrajectory run;
  int refused = 0;
  PoseSeries scan_only;  ///< eval::scanOnlyPoses: what the agreement compares with the wheels
  algo::SensorAgreement agreement;
};

MatchPass matchPass(const Dataset& d, const MatchFlags& flags) {
  MatchPass pass;
  const eval::ScanPoints points = eval::matchScanPoints(d, flags.deskew, flags.stamp_is_last_beam);
  pass.refused = points.refused;
  eval::MatchTrajectoryOptions options{flags.params, flags.stamp_is_last_beam};
  options.measure_odometry_noise = flags.odometry_noise == "measured";
  pass.run = eval::matchTrajectory(d, points, options);
  pass.scan_only = eval::scanOnlyPoses(d, points, options, pass.run);
  pass.agreement = eval::scanAgreement(d, pass.scan_only);
  return pass;
}

/// --sync auto (algo::syncOntoScanClock, as calibrate does): returns the shift (0: none). The
/// delay is first measured on the scans as measured where the de-skew reads the late clocks.
double syncAndMatchAgain(Dataset& d, const MatchFlags& flags, MatchPass& pass) {
  if (flags.sync != "auto") return 0.0;
  const eval::DatasetCalibrationParams calibrate;  // its thresholds, not a copy of them
  const algo::SensorAgreement first =
      eval::syncStartAgreement(d, pass.agreement, flags.deskew, flags.stamp_is_last_beam);
  return algo::syncOntoScanClock(d, first, calibrate.min_sync_lag_s, calibrate.min_refine_lag_s,
                                 [&](const Dataset& s) {
                                   pass = matchPass(s, flags);
                                   return std::vector<PoseSeries>{pass.scan_only};
                                 });
}

/// Whether the matches were fused with the odometry at all (an odometry sigma of 0: not).
bool fusedWithOdometry(const eval::MatchTrajectory& run) {
  return run.odometry_sigma_m > 0.0 && run.odometry_sigma_rad > 0.0;
}

/// The odometry noise the matches were fused with and how it was found (docs/matching.md).
nlohmann::ordered_json odometryNoiseJson(const eval::MatchTrajectory& run) {
  const auto& measured = run.odometry_noise;
  nlohmann::ordered_json out = {
      {"source", !fusedWithOdometry(run) ? "off"
                 : measured              ? "measured"
                                         : "given"},
      {"sigma_m", run.odometry_sigma_m},
      {"sigma_deg", run.odometry_sigma_rad * kDegPerRad},
      {"steps", measured ? nlohmann::ordered_json(measured->steps) : nullptr},
      {"min_support", measured ? nlohmann::ordered_json(measured->min_support) : nullptr}};
  return out;
}

void printOdometryNoise(const eval::MatchTrajectory& run) {
  if (!fusedWithOdometry(run)) return;
  std::printf("fused with an odometry noise per scan step of %.4f m, %.3f deg",
              run.odometry_sigma_m, run.odometry_sigma_rad * kDegPerRad);
  if (const auto& m = run.odometry_noise)
    std::printf(
        ": measured against the scans matched alone, on the %zu steps to scans the map explains "
        "best (support >= %.2f)\n",
        m->steps, m->min_support);
  else
    std::printf(" (as given)\n");
}

nlohmann::ordered_json residualJson(const eval::ErrorStats& s) {
  if (!s.ok) return nullptr;
  return {{"median", s.median}, {"p95", s.p95}};
}

nlohmann::ordered_json summaryJson(const MatchFlags& f, const eval::MatchTrajectory& run,
                                   int deskew_refused, double seconds,
                                   nlohmann::ordered_json agreement) {
  const algo::KeyframeOdometry& t = run.tracked;
  const std::size_t attempted = t.scans.size() - 1;
  const algo::IcpParams& icp = f.params.icp;
  return {
      {"dataset", f.dataset},
      {"deskew", f.deskew},
      {"deskew_refused", deskew_refused},
      {"scans", t.scans.size()},
      {"matched", t.matched},
      {"fallbacks", t.fallbacks},
      {"rejected", t.rejected},
      {"unsupported", t.unsupported},
      {"sparse", t.sparse},
      {"not_converged", notConverged(t)},
      {"points_per_scan_median", pointsPerScanMedian(t)},
      {"converged_percent", 100.0 * double(t.matched) / double(attempted)},
      {"keyframes", t.keyframes},
      {"odometry_guesses", run.odometry_guesses},
      {"hypotheses", hypothesesJson(run)},
      {"residual_rms_m", residualJson(acceptedResiduals(t))},
      {"odometry_noise", odometryNoiseJson(run)},
      {"sensor_agreement", std::move(agreement)},
      {"seconds", seconds},
      {"params",
       {{"max_iterations", icp.max_iterations},
        {"max_correspondence_distance_m", icp.max_correspondence_distance_m},
        {"outlier_sigmas", icp.outlier_sigmas},
        {"trim_fraction", icp.trim_fraction},
        {"line_max_thickness", icp.line_max_thickness},
        {"keyframe_distance_m", f.params.keyframe_distance_m},
        {"keyframe_angle_deg", f.keyframe_angle_deg},
        {"voxel_size_m", f.params.submap.voxel_size_m},
        {"submap_radius_m", f.params.submap.max_distance_m},
        {"submap_travel_m", f.params.submap.max_travel_m},
        {"max_range_m", f.params.max_range_m},
        {"odometry_sigma_m", f.params.odometry_sigma_m},
        {"odometry_sigma_deg", f.odometry_sigma_deg},
        {"odometry_noise", f.odometry_noise},
        {"max_correction_m", f.params.max_correction_m},
        {"max_correction_deg", f.params.max_correction_rad * kDegPerRad},
        {"hypothesis_separation_m", f.params.hypothesis_separation_m},
        {"hypothesis_separation_deg", f.params.hypothesis_separation_rad * kDegPerRad},
        {"support_distance_m", f.params.support_distance_m},
        {"min_support_fraction", f.params.min_support_fraction},
        {"preference_cost_ratio", f.params.preference_cost_ratio}}},
      {"trajectory_file", f.trajectory.empty() ? nullptr : nlohmann::ordered_json(f.trajectory)},
      {"matches_file", f.out.empty() ? nullptr : nlohmann::ordered_json(f.out)}};
}

void printGuesses(const eval::MatchTrajectory& run) {
  const algo::KeyframeOdometry& t = run.tracked;
  std::printf(
      "guesses: odometry for %zu scans, gyro for %zu; they disagreed on %zu, matched from "
      "each; poses taken from",
      run.odometry_guesses, run.gyro_guesses, t.multi_hypothesis);
  const char* separator = "";
  for (const auto& [source, name] : algo::kGuessSourceNames) {
    std::printf("%s %.*s %zu", separator, static_cast<int>(name.size()), name.data(),
                t.won_by[static_cast<std::size_t>(source)]);
    separator = ",";
  }
  std::printf("\n");
}

void checkMatchOutputs(const MatchFlags& flags) {
  checkInputDataset(flags.dataset, "DATASET");
  OutputGuard guard(flags.force);
  guard.input(flags.dataset, "DATASET");
  for (const auto& [file, option] : {std::pair{flags.out, "--out"},
                                     {flags.trajectory, "--trajectory"},
                                     {flags.json_out, "--json"}})
    if (!file.empty()) guard.file(file, option);
  guard.check();
}

/// Says why a match fails throughout where the scans hold too few points for ICP.
void printSparseNote(const algo::KeyframeOdometry& t, const algo::KeyframeOdometryParams& p) {
  const std::size_t median = pointsPerScanMedian(t);
  if (t.scans.size() < 2 || 10 * t.sparse < t.scans.size() - 1) return;
  std::printf(
      "match: note: %zu of %zu scans hold fewer than %zu points within %g m (median %zu a "
      "scan): ICP cannot place them, the guesses do. The lidar saw little: open space beyond "
      "its range, or a blocked or faulty head\n",
      t.sparse, t.scans.size() - 1, p.icp.min_inliers, p.max_range_m, median);
}

/// What stdout says of a match: the counts, the guesses, the residual, the de-skew, the sync,
/// the sensor agreement and the files written.
void printMatch(const MatchFlags& flags, const MatchPass& pass,
                const nlohmann::ordered_json& summary, double seconds, double clock_sync_s) {
  const algo::KeyframeOdometry& t = pass.run.tracked;
  std::printf(
      "matched %zu of %zu scans against the local map (%.2f %%), %zu fell back to a "
      "guess (%zu converged beyond the correction limit, %zu without the map's support, %zu "
      "with under %zu points, %zu without convergence); %zu keyframes\n",
      t.matched, t.scans.size() - 1, summary["converged_percent"].get<double>(), t.fallbacks,
      t.rejected, t.unsupported, t.sparse, flags.params.icp.min_inliers, notConverged(t),
      t.keyframes);
  printSparseNote(t, flags.params);
  printGuesses(pass.run);
  printOdometryNoise(pass.run);
  const eval::ErrorStats residual = acceptedResiduals(t);
  if (residual.ok)
    std::printf("point-to-line residual of the accepted matches: median %.4f m, p95 %.4f m\n",
                residual.median, residual.p95);
  std::printf("de-skew %s", flags.deskew.c_str());
  if (flags.deskew != "none") std::printf(" (%d scans refused, matched as measured)", pass.refused);
  std::printf("; %.2f s\n", seconds);
  if (clock_sync_s != 0.0)
    std::printf(
        "--sync auto: the scans lagged the wheels by %.3f s; the wheels (and the gyro) moved "
        "onto the scans' clock and the scans matched again (the agreement below is after it)\n",
        clock_sync_s);
  std::printf("%s", algo::agreementText(pass.agreement).c_str());
  for (const auto& [file, what] : {std::pair{flags.out, "matches"},
                                   {flags.trajectory, "trajectory"},
                                   {flags.json_out, "summary"}})
    if (!file.empty()) std::printf("wrote %s %s\n", what, file.c_str());
  if (flags.out.empty() && flags.trajectory.empty() && flags.json_out.empty())
    std::printf("no --out, --trajectory or --json: nothing written\n");
}

int runMatch(MatchFlags flags) {
  checkMatchOutputs(flags);
  flags.params.keyframe_angle_rad = flags.keyframe_angle_deg / kDegPerRad;
  flags.params.odometry_sigma_rad = flags.odometry_sigma_deg / kDegPerRad;
  const auto begin = std::chrono::steady_clock::now();
  Dataset d = eval::readDataset(flags.dataset);
  if (d.scans.size() < 2) throw InputError(flags.dataset, "needs at least two scans to match");
  double clock_sync_s = 0.0;
  const MatchPass pass = [&] {
    CommandProgress progress(1, "runs", "match", !flags.quiet);
    StageReporter stages(flags.dataset, 1);
    stages.begin("match");
    MatchPass first = matchPass(d, flags);
    clock_sync_s = syncAndMatchAgain(d, flags, first);
    return first;
  }();
  const eval::MatchTrajectory& run = pass.run;
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  if (!flags.out.empty()) writeFileAtomic(flags.out, eval::formatTrackedMatches(run));
  if (!flags.trajectory.empty())
    writeFileAtomic(flags.trajectory, eval::formatTum(run.T_world_base, flags.trajectory));
  auto summary = summaryJson(flags, run, pass.refused, seconds,
                             algo::agreementJson(pass.agreement, algo::encodersFrom(d.info)));
  summary["clock_sync_s"] = clock_sync_s;
  if (!flags.json_out.empty()) writeFileAtomic(flags.json_out, summary.dump(2) + "\n");
  printMatch(flags, pass, summary, seconds, clock_sync_s);
  const algo::KeyframeOdometry& t = run.tracked;
  return refusalExitCode(t.matched == 0, t.fallbacks > 0, flags.strict);
}

}  // namespace

namespace {

/// The footer, the dataset, what is written, and how scans are read and de-skewed.
void addMatchInOut(CLI::App* cli, const std::shared_ptr<MatchFlags>& flags) {
  cli->footer(
      "Matches every scan (point-to-line ICP) against a point map of the keyframes of the last\n"
      "40 m of travel. Guesses: the odometry, the gyro's turn, the last step, standing still;\n"
      "where they disagree each is matched and the pose the map explains best is kept. A match\n"
      "is accepted when the map supports the scan, never for agreeing with a guess; otherwise\n"
      "the best supported guess is taken and counted as a fallback (docs/matching.md).\n"
      "--trajectory FILE writes the base poses as TUM, --out FILE one JSON line per scan, --json\n"
      "FILE the summary. Exit 3 when no scan matched, or with --strict when any fell back.");
  cli->add_option("DATASET", flags->dataset, "dataset directory (read only)")->required();
  cli->add_option("--out", flags->out, "write one JSON line per scan after the first to FILE")
      ->check(outputPath());
  cli->add_option("--trajectory", flags->trajectory,
                  "write the base trajectory at the scans' first beams to FILE (TUM)")
      ->check(outputPath());
  addJson(cli, *flags, "the summary (counts, timing, parameters)");
  addForce(cli, *flags, "existing output files");
  addStrict(cli, *flags, "when any scan fell back, not only all");
  addQuiet(cli, *flags);
  const std::vector<std::string> deskews = namesOf(algo::kDeskewMethodNames);  // "none" first
  cli->add_option("--deskew", flags->deskew,
                  "de-skew each scan with this method first (scans it refuses are matched as "
                  "measured; docs/deskew.md); none: match the scans as measured")
      ->check(oneOf("de-skew method", deskews))
      ->capture_default_str();
  cli->add_flag("--stamp-is-last-beam", flags->stamp_is_last_beam,
                "the scans' stamps mark their last beam, not their first");
  cli->add_option("--sync", flags->sync,
                  "auto: where the sensor agreement finds the scans lagging the wheels by more "
                  "than 20 ms, move the wheels' (and the gyro's) stamps onto the scans' clock and "
                  "match again (the guesses and de-skew read them at each beam's time); none: "
                  "the stamps as logged")
      ->check(oneOf("sync", {"auto", "none"}))
      ->capture_default_str();
}

/// The registration and the local map of keyframes it matches against.
void addMatchMap(CLI::App* cli, const std::shared_ptr<MatchFlags>& flags) {
  algo::IcpParams& icp = flags->params.icp;
  addIcpOptions(cli, icp);
  cli->add_option("--keyframe-distance", flags->params.keyframe_distance_m,
                  "a scan this far (m) from the keyframe becomes a keyframe")
      ->check(positive())
      ->capture_default_str();
  cli->add_option("--keyframe-angle", flags->keyframe_angle_deg,
                  "... or one turned this much (deg)")
      ->check(positive())
      ->capture_default_str();
  algo::LocalSubmapParams& submap = flags->params.submap;
  cli->add_option(
         "--voxel-size", submap.voxel_size_m,
         "no two local map points closer than this (m): keyframe points enter where there are none")
      ->check(positive())
      ->capture_default_str();
  cli->add_option("--submap-radius", submap.max_distance_m,
                  "map points farther than this (m) from the robot are dropped")
      ->check(positive())
      ->capture_default_str();
  cli->add_option("--submap-travel", submap.max_travel_m,
                  "map points inserted more than this many metres of travel ago are dropped")
      ->check(nonNegative())
      ->capture_default_str();
}

/// Which guesses are tried, how far they are trusted, and when a match is accepted.
void addMatchGuesses(CLI::App* cli, const std::shared_ptr<MatchFlags>& flags) {
  cli->add_option("--max-range", flags->params.max_range_m,
                  "points farther than this (m) from the sensor are not matched")
      ->check(positive())
      ->capture_default_str();
  cli->add_option("--odometry-noise", flags->odometry_noise,
                  "measured: fuse each match with the odometry's noise per scan step measured "
                  "on the recording (its steps against the scans matched alone, where the map "
                  "explains them best); given: --odometry-sigma and --odometry-sigma-angle")
      ->check(oneOf("odometry noise", {"measured", "given"}))
      ->capture_default_str();
  cli->add_option("--odometry-sigma", flags->params.odometry_sigma_m,
                  "odometry noise per scan step (m) the match is fused with where not measured "
                  "(--odometry-noise given, or too few steps); 0: the match alone")
      ->check(nonNegative())
      ->capture_default_str();
  cli->add_option("--odometry-sigma-angle", flags->odometry_sigma_deg,
                  "... and its heading noise per scan step (deg); 0: the match alone")
      ->check(nonNegative())
      ->capture_default_str();
  cli->add_option("--min-support", flags->params.min_support_fraction,
                  "a converged match is accepted when at least this fraction of the scan's "
                  "points lies within 0.1 m of the map (scan support)")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  cli->add_option("--preference-ratio", flags->params.preference_cost_ratio,
                  "where the guesses disagree, a later guess's match replaces the odometry's only "
                  "when its scan-support cost is below 1/R of it")
      ->check(CLI::Range(1.0, 1e9))
      ->capture_default_str();
  cli->add_flag_callback(
      "--single-guess",
      [flags] {
        flags->params.hypothesis_separation_m = std::numeric_limits<double>::infinity();
        flags->params.hypothesis_separation_rad = std::numeric_limits<double>::infinity();
      },
      "match from the first guess only (the odometry; the last step without one), not from "
      "each where the guesses disagree: the matcher before hypotheses, for comparison");
}

}  // namespace

Command addMatchCommand(CLI::App& app) {
  auto flags = std::make_shared<MatchFlags>();
  auto* cli = app.add_subcommand(
      "match", "Lidar odometry: each scan matched against a local map of keyframes.");
  addMatchInOut(cli, flags);
  addMatchMap(cli, flags);
  addMatchGuesses(cli, flags);
  return {cli, [flags] { return runMatch(*flags); }};
}

}  // namespace slamprep::app
