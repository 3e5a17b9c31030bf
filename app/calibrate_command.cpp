// `slamprep calibrate`: odometry calibration (docs/calibration.md) on a dataset or on Censi
// interval records.
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <numbers>
#include <sstream>

#include "algo/calibration/calibration_json.hpp"
#include "algo/deskew/deskew.hpp"
#include "algo/timing/dataset_stamps.hpp"
#include "app/choices.hpp"
#include "app/commands.hpp"
#include "app/exit_codes.hpp"
#include "app/icp_options.hpp"
#include "app/outputs.hpp"
#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "eval/bench/calibration_run.hpp"
#include "eval/bench/command_progress.hpp"
#include "eval/bench/ros2_params.hpp"
#include "eval/formats/tum.hpp"

namespace slamprep::app {
namespace {

struct CalibrateFlags {
  std::string dataset;
  std::string method = "all";
  std::string motion = "icp";   // what real logs have; groundtruth is the oracle
  std::string deskew = "auto";  // --deskew: how scans are de-skewed before matching
  std::string intervals_out;    // --intervals: write the intervals used as Censi records
  std::string tuples_in;        // --tuples: run on Censi records instead of the dataset's motion
  std::string json_out;
  std::string odometry_out;     // --odometry-out: the odometry re-integrated with the best result
  std::string ros2_out;         // --ros2-params: diff_drive_controller + static transform YAML
  std::string nominal;          // --nominal r_L,r_R,b
  std::string stamps = "auto";  // auto: jittered constant-rate streams back on their grids
  double trim_sigmas = algo::TrimParams{}.threshold_sigmas;
  std::vector<std::string> squares;  // extra UMBmark square-run datasets
  // The shared interval policy (algo::IntervalParams: every scan match) unless overridden.
  double keyframe_cm = algo::IntervalParams{}.keyframe_translation_m * 100.0;
  double keyframe_deg = algo::IntervalParams{}.keyframe_rotation_rad * 180.0 / std::numbers::pi;
  double side_m = algo::UmbmarkParams{}.side_m;  // the shipped umbmark_cw/ccw.yaml squares
  algo::IcpParams icp;                           // the scan matcher between consecutive scans
  bool time_offset = false;
  bool sideslip = false;
  bool loop_closure = false;
  bool stamp_is_last_beam = false;
  bool strict = false;
  bool quiet = false;
  bool force = false;
};

// Lengths in mm, the yaw in degrees: what a person reads.
std::string human(double value, int i) {
  std::ostringstream s;
  s << std::fixed;
  if (i == 5)
    s << std::setprecision(3) << value * 180.0 / std::numbers::pi << " deg";
  else
    s << std::setprecision(3) << value * 1000.0 << " mm";
  return s.str();
}

void printTable(const std::vector<algo::CalibrationRun>& rows,
                const std::optional<algo::CalibrationTruth>& truth_of) {
  std::optional<Eigen::VectorXd> truth;
  if (truth_of) truth = truth_of->values();
  for (const algo::CalibrationRun& row : rows) {
    const auto& r = row.result;
    std::cout << "\n" << algo::calibrationMethodName(row.method) << ": ";
    if (!r.ok) {
      std::cout << "REFUSED: " << r.reason << "\n";
      continue;
    }
    std::cout << r.intervals_used << " intervals/runs, condition number " << std::setprecision(3)
              << r.condition_number << ", " << r.intervals_trimmed << " trimmed\n";
    for (const algo::TrimmedInterval& t : r.trimmed_worst)
      std::cout << "  trimmed " << std::fixed << std::setprecision(3) << t.t0_s << ".." << t.t1_s
                << " s: " << t.reason << " (" << std::setprecision(1) << t.residual_sigmas
                << " robust sigmas)\n"
                << std::defaultfloat;
    std::cout << "  " << std::left << std::setw(10) << "param" << std::setw(16) << "estimate"
              << std::setw(16) << "1-sigma";
    if (truth)
      std::cout << std::setw(16) << "truth" << std::setw(14) << "error"
                << "error %";
    std::cout << "\n";
    const Eigen::VectorXd v = algo::calibrationValues(r), s = r.sigma();
    for (int i = 0; i < v.size(); ++i) {
      std::cout << "  " << std::setw(10) << algo::kCalibrationKeys[i] << std::setw(16)
                << human(v(i), i) << std::setw(16)
                << (r.covariance.size() > 0 ? human(s(i), i) : "n/a");
      if (truth) {
        const double e = algo::calibrationError(v, *truth, i);
        std::ostringstream pct;
        if (std::abs((*truth)(i)) > 1e-12)
          pct << std::fixed << std::setprecision(4) << 100.0 * e / std::abs((*truth)(i)) << " %";
        else
          pct << "-";
        std::cout << std::setw(16) << human((*truth)(i), i) << std::setw(14) << human(e, i)
                  << pct.str();
      }
      std::cout << "\n";
    }
  }
}

eval::DatasetCalibrationParams paramsOf(const CalibrateFlags& flags) {
  eval::DatasetCalibrationParams p;
  p.dataset = flags.dataset;
  if (flags.method != "all") p.methods = {*algo::parseCalibrationMethod(flags.method)};
  p.only_applicable = flags.method == "all";
  p.tuples = flags.tuples_in;
  p.squares = flags.squares;
  p.motion.from_icp = flags.motion == "icp";
  p.regularize_stamps = flags.stamps == "auto";
  p.motion.deskew = flags.deskew;
  p.motion.stamp_is_last_beam = flags.stamp_is_last_beam;
  p.motion.intervals.keyframe_translation_m = flags.keyframe_cm / 100.0;
  p.motion.intervals.keyframe_rotation_rad = flags.keyframe_deg * std::numbers::pi / 180.0;
  p.motion.icp = flags.icp;
  p.motion.loop_closure = flags.loop_closure;
  p.params.umbmark.side_m = flags.side_m;
  p.params.ceres.estimate_time_offset = flags.time_offset;
  p.params.joint.estimate_sideslip = flags.sideslip;  // ceres starts from joint's k
  p.params.ceres.estimate_sideslip = flags.sideslip;
  p.params.trim.enabled = flags.trim_sigmas > 0.0;
  if (p.params.trim.enabled) p.params.trim.threshold_sigmas = flags.trim_sigmas;
  if (!flags.nominal.empty()) {
    const auto v = parseList(flags.nominal, "--nominal", {"r_L", "r_R", "b"});
    if (!(v[0] > 0.0 && v[1] > 0.0 && v[2] > 0.0))
      throw InputError("--nominal", "r_L, r_R and b must be > 0");
    p.nominal = DiffDriveParams{v[0], v[1], v[2]};
  }
  return p;
}

void checkPaths(const CalibrateFlags& flags) {
  if (!flags.dataset.empty()) checkInputDataset(flags.dataset, "DATASET");
  if (!flags.tuples_in.empty()) checkInputFile(flags.tuples_in, "--tuples");
  for (const std::string& dir : flags.squares) checkInputDataset(dir, "--square");
  if (!flags.json_out.empty()) checkOutputFile(flags.json_out, "--json", flags.force);
  if (!flags.intervals_out.empty())
    checkOutputFile(flags.intervals_out, "--intervals", flags.force);
  if (!flags.odometry_out.empty())
    checkOutputFile(flags.odometry_out, "--odometry-out", flags.force);
  if (!flags.ros2_out.empty()) checkOutputFile(flags.ros2_out, "--ros2-params", flags.force);
  if ((!flags.odometry_out.empty() || !flags.ros2_out.empty()) && flags.dataset.empty())
    throw InputError("--odometry-out/--ros2-params", "need DATASET (its encoders and mount)");
  if (flags.loop_closure && (flags.motion != "icp" || !flags.tuples_in.empty()))
    throw InputError("--loop-closure",
                     "closes the loops of scan-matched motion: needs --motion icp, not --tuples");
  for (const std::string& out :
       {flags.json_out, flags.intervals_out, flags.odometry_out, flags.ros2_out})
    if (!out.empty() && !flags.dataset.empty()) checkNotInside(out, flags.dataset, "output");
}

// --odometry-out and --ros2-params from the best result; an error when no method is ok.
void writeBestOutputs(const CalibrateFlags& flags, const eval::DatasetCalibration& c) {
  if (flags.odometry_out.empty() && flags.ros2_out.empty()) return;
  const algo::CalibrationRun* best = algo::bestRun(c.runs);
  if (!best) throw InputError(flags.dataset, "no method gave a result: nothing to write");
  const std::string method(algo::calibrationMethodName(best->method));
  if (!flags.odometry_out.empty()) {
    const PoseSeries odometry = eval::calibratedOdometry(c, best->result.geometry);
    writeFileAtomic(flags.odometry_out, eval::formatTum(odometry, flags.odometry_out));
    std::cerr << "calibrate: odometry with the " << method << " geometry written to "
              << flags.odometry_out << "\n";
  }
  if (!flags.ros2_out.empty()) {
    const bool mount = best->result.estimates_mount;
    const eval::Ros2ParamsInput in{c.nominal,
                                   best->result.geometry,
                                   mount ? best->result.T_base_lidar : c.T_base_lidar,
                                   method,
                                   mount,
                                   c.relative_to_odometry.has_value()};
    writeFileAtomic(flags.ros2_out, eval::formatRos2Params(in));
    std::cerr << "calibrate: ROS 2 parameters (" << method << ") written to " << flags.ros2_out
              << "\n";
  }
}

int runCalibrate(const CalibrateFlags& flags) {
  checkPaths(flags);
  const eval::DatasetCalibration c = [&] {
    eval::CommandProgress progress(1, "runs", "calibrate", !flags.quiet);
    eval::StageReporter stages(flags.dataset.empty() ? "calibrate" : flags.dataset, 1);
    stages.begin("calibrate");
    return eval::calibrateDataset(paramsOf(flags));
  }();
  std::cerr << algo::stampsSummary(c.stamps);
  if (c.failed_matches > 0)
    std::cerr << "calibrate: " << c.failed_matches << " scan matches failed (chains broken)\n";
  if (c.from_motion)
    std::cerr << "calibrate: " << c.intervals.intervals.size() << " intervals ("
              << c.intervals.dropped_standstill << " standing still, "
              << c.intervals.dropped_uncovered << " without encoder data dropped)\n";
  if (c.loops)
    std::cerr << "calibrate: loop closure: " << c.loops->used << " of " << c.loops->candidates
              << " direct matches used; largest heading change of one link "
              << c.loops->max_link_change_rad * 180.0 / std::numbers::pi * 1e3 << " mdeg\n";
  if (!flags.intervals_out.empty())
    algo::writeIntervalRecords(flags.intervals_out, c.intervals.intervals);
  for (const algo::CalibrationRun& run : c.runs) {
    if (run.time_offset_s)
      std::cerr << "calibrate: ceres time offset " << *run.time_offset_s * 1e3 << " ms +- "
                << run.time_offset_sigma_s * 1e3 << " ms\n";
    if (run.sideslip_s)
      std::cerr << "calibrate: " << algo::calibrationMethodName(run.method) << " sideslip k "
                << *run.sideslip_s * 1e3 << " ms +- " << run.sideslip_sigma_s * 1e3
                << " ms (sideways speed k v w)\n";
  }
  printTable(c.runs, c.truth);
  for (const eval::NotApplicable& n : c.not_applicable)
    std::cout << "\n"
              << algo::calibrationMethodName(n.method) << ": not applicable: " << n.reason << "\n";
  if (c.relative_to_odometry)
    std::cout << "\nrelative to the log's odometry: "
              << algo::odometryRelativeMeaning(*c.relative_to_odometry) << "\n";
  if (!flags.json_out.empty()) algo::writeCalibrationJson(flags.json_out, c.runs, c.truth);
  writeBestOutputs(flags, c);
  const auto refused = std::count_if(c.runs.begin(), c.runs.end(),
                                     [](const algo::CalibrationRun& r) { return !r.result.ok; });
  return refusalExitCode(refused == static_cast<long>(c.runs.size()), refused > 0, flags.strict);
}

}  // namespace

Command addCalibrateCommand(CLI::App& app) {
  auto flags = std::make_shared<CalibrateFlags>();
  auto* cli = app.add_subcommand("calibrate",
                                 "Odometry calibration: wheel radii, wheel base and lidar mount.");
  cli->footer(
      "r_L, r_R, b (and the lidar mount) from wheel encoders plus the lidar's motion\n"
      "(docs/calibration.md). --method all runs the methods that apply to the data; one that\n"
      "does not (umbmark without square runs) is reported as not applicable. Exit 3 when every\n"
      "method run refused, or with --strict when any did.");
  cli->add_option("DATASET", flags->dataset, "dataset directory");
  std::vector<std::string> methods = algo::calibrationMethodNames();
  methods.emplace_back("all");
  cli->add_option("--method", flags->method,
                  "calibration method, or all: the ones that apply to the data")
      ->check(oneOf("method", methods))
      ->capture_default_str();
  cli->add_option("--motion", flags->motion,
                  "lidar motion from ICP scan matching or from ground truth (oracle)")
      ->check(oneOf("motion", {"icp", "groundtruth"}))
      ->capture_default_str();
  cli->add_option("--stamps", flags->stamps,
                  "auto: match scans on stamps put back on their constant-rate grid where a "
                  "stream (encoders, odometry, IMU, scans) is measurably jittered "
                  "(docs/calibration.md, \"Jittered stamps\"); raw: as logged. Outputs keep "
                  "the log's stamps")
      ->check(oneOf("stamps", {"auto", "raw"}))
      ->capture_default_str();
  std::vector<std::string> deskews = {"auto"};
  for (auto m : algo::allDeskewMethods()) deskews.emplace_back(algo::deskewMethodName(m));
  cli->add_option("--deskew", flags->deskew,
                  "with --motion icp: de-skew scans with this method before matching them. auto: "
                  "imu when the log has one (independent of the wheel geometry being "
                  "calibrated), else odom-linear with the nominal geometry, none on instantaneous "
                  "scans (time_increment 0); none: raw scans, which motion distortion biases")
      ->check(oneOf("de-skew method", deskews))
      ->capture_default_str();
  cli->add_flag("--stamp-is-last-beam", flags->stamp_is_last_beam,
                "the scans' stamps mark their last beam, not their first");
  cli->add_option("--intervals", flags->intervals_out,
                  "write the intervals used as Censi records (JSON lines) to FILE");
  cli->add_option("--tuples", flags->tuples_in, "run on Censi interval records instead");
  cli->add_option("--json", flags->json_out,
                  "write one object per method to FILE (what deskew and export read with "
                  "--calibration)");
  cli->add_option("--odometry-out", flags->odometry_out,
                  "write the odometry re-integrated with the best result's geometry to FILE "
                  "(TUM; score it with `slamprep score relations`)");
  cli->add_option("--ros2-params", flags->ros2_out,
                  "write the best result as ros2_control diff_drive_controller parameters and "
                  "the base_link -> laser static transform to FILE (ROS 2 parameter YAML)");
  cli->add_option("--nominal", flags->nominal,
                  "r_L,r_R,b in metres: the geometry the odometry uses (default: dataset.json's); "
                  "a log without encoder ticks gets its wheel increments derived from its "
                  "odometry poses with it, and the estimates are relative to it");
  cli->add_option("--trim-sigmas", flags->trim_sigmas,
                  "drop intervals whose residual against a first fit exceeds N robust (MAD) "
                  "sigmas, refit until the kept set repeats; 0: keep every interval")
      ->check(nonNegative())
      ->capture_default_str();
  cli->add_flag("--force", flags->force,
                "replace existing output files; the old ones stay until the new are complete");
  cli->add_flag("--strict", flags->strict, "exit 3 when any method refused, not only all");
  cli->add_flag("-q,--quiet", flags->quiet, "No progress output");
  cli->add_option("--keyframe-cm", flags->keyframe_cm,
                  "new interval every N cm of lidar motion (0: every scan match, as the bench)")
      ->check(nonNegative())
      ->capture_default_str();
  cli->add_option("--keyframe-deg", flags->keyframe_deg, "... or every N degrees")
      ->check(nonNegative())
      ->capture_default_str();
  addIcpOptions(cli, flags->icp);
  cli->add_option("--square", flags->squares, "UMBmark square-run dataset (repeatable)");
  cli->add_option("--side", flags->side_m, "UMBmark square side (m)")
      ->check(positive())
      ->capture_default_str();
  cli->add_flag("--time-offset", flags->time_offset,
                "ceres: also estimate a constant encoder-to-lidar clock offset");
  cli->add_flag("--sideslip", flags->sideslip,
                "joint and ceres: also estimate a sideslip k, the base moving sideways at k v w in "
                "turns (not with --time-offset)")
      ->excludes("--time-offset");
  cli->add_flag("--loop-closure", flags->loop_closure,
                "with --motion icp: where the matched path revisits a place (10 s or more later, "
                "within 0.3 m and 20 deg) match the two scans directly and spread the heading "
                "drift this reveals back over the matches. Chained matches drift in heading, which "
                "reads as r_R != r_L and which no sigma of the same log can show");
  return {cli, [flags] { return runCalibrate(*flags); }};
}

}  // namespace slamprep::app
