// `slamprep calibrate`: odometry calibration (docs/calibration.md) on a dataset or on Censi
// interval records.
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <numbers>
#include <sstream>

#include "slamprep/algo/agreement/agreement_report.hpp"
#include "slamprep/algo/calibration/calibration_json.hpp"
#include "slamprep/algo/deskew/deskew.hpp"
#include "slamprep/algo/timing/dataset_stamps.hpp"
#include "slamprep/app/calibration_tables.hpp"
#include "slamprep/app/choices.hpp"
#include "slamprep/app/command_progress.hpp"
#include "slamprep/app/commands.hpp"
#include "slamprep/app/common_flags.hpp"
#include "slamprep/app/exit_codes.hpp"
#include "slamprep/app/icp_options.hpp"
#include "slamprep/app/outputs.hpp"
#include "slamprep/core/atomic_file.hpp"
#include "slamprep/core/error.hpp"
#include "slamprep/eval/formats/ros2_params.hpp"
#include "slamprep/eval/formats/tum.hpp"
#include "slamprep/eval/pipeline/calibration_run.hpp"
#include "slamprep/eval/pipeline/recordings_calibration.hpp"

namespace slamprep::app {
namespace {

struct CalibrateFlags : CommonFlags {
  std::vector<std::string> datasets;  // several: recordings of one robot, combined
  std::string method = "all";
  std::string motion = "map";   // scan-to-map: 2-4x the accuracy of chained ICP (docs)
  std::string deskew = "auto";  // --deskew: how scans are de-skewed before matching
  std::string intervals_out;    // --intervals: write the intervals used as Censi records
  std::string tuples_in;        // --tuples: run on Censi records instead of the dataset's motion
  std::string odometry_out;     // --odometry-out: the odometry re-integrated with the best result
  std::string ros2_out;         // --ros2-params: diff_drive_controller + static transform YAML
  std::string nominal;          // --nominal r_L,r_R,b
  std::string stamps = "auto";  // auto: jittered constant-rate streams back on their grids
  double trim_sigmas = algo::TrimParams{}.threshold_sigmas;
  double validate_fraction = 0.0;    // --validate-fraction: hold out the last F of the scans
  bool leave_one_out = false;        // --leave-one-out: each recording scored with the others'
  std::vector<std::string> squares;  // extra UMBmark square-run datasets
  // The shared interval policy (algo::IntervalParams: every scan match) unless overridden.
  double keyframe_cm = algo::IntervalParams{}.keyframe_translation_m * 100.0;
  double keyframe_deg = algo::IntervalParams{}.keyframe_rotation_rad * 180.0 / std::numbers::pi;
  double side_m = algo::UmbmarkParams{}.side_m;  // the shipped umbmark_cw/ccw.yaml squares
  algo::IcpParams icp;                           // the scan matcher between consecutive scans
  bool time_offset = false;
  bool sideslip = false;
  bool loop_closure = false;
  bool exclude_disagreement = false;   // --exclude-disagreement
  std::string sync = "auto";           // --sync
  std::string lidar_mount = "centre";  // --lidar-mount: what direct and model take the mount as
  std::string mount_prior = "2,2";     // --mount-prior: 1-sigmas in cm, deg, or none
  bool stamp_is_last_beam = false;
};

std::optional<DiffDriveParams> nominalOf(const CalibrateFlags& flags) {
  if (flags.nominal.empty()) return std::nullopt;
  const auto v = parseList(flags.nominal, "--nominal", {"r_L", "r_R", "b"});
  if (!(v[0] > 0.0 && v[1] > 0.0 && v[2] > 0.0))
    throw InputError("--nominal", "r_L, r_R and b must be > 0");
  return DiffDriveParams{v[0], v[1], v[2]};
}

// --mount-prior CM,DEG (the prior's 1-sigmas) or none.
void mountPriorOf(const CalibrateFlags& flags, eval::DatasetCalibrationParams& p) {
  p.mount_prior = flags.mount_prior != "none";
  if (!p.mount_prior) return;
  const auto v = parseList(flags.mount_prior, "--mount-prior", {"sigma_cm", "sigma_deg"});
  if (!(v[0] > 0.0 && v[1] > 0.0))
    throw InputError("--mount-prior", "the 1-sigmas must be > 0 (none: no prior)");
  p.mount_prior_sigma_xy_m = v[0] / 100.0;
  p.mount_prior_sigma_yaw_rad = v[1] * std::numbers::pi / 180.0;
}

eval::RecordingsCalibrationParams paramsOf(const CalibrateFlags& flags) {
  eval::RecordingsCalibrationParams recordings;
  recordings.datasets = flags.datasets;
  recordings.validate_fraction = flags.validate_fraction;
  recordings.leave_one_out = flags.leave_one_out;
  recordings.held_out.stamp_is_last_beam = flags.stamp_is_last_beam;
  eval::DatasetCalibrationParams& p = recordings.base;
  if (flags.method != "all")
    p.methods = {parseName(algo::kCalibrationMethodNames, flags.method, "method", "--method")};
  p.only_applicable = flags.method == "all";
  p.tuples = flags.tuples_in;
  p.squares = flags.squares;
  p.motion.source = parseName(eval::kMotionSourceNames, flags.motion, "motion", "--motion");
  p.regularize_stamps = flags.stamps == "auto";
  p.motion.deskew = flags.deskew;
  p.motion.stamp_is_last_beam = flags.stamp_is_last_beam;
  p.motion.intervals.keyframe_translation_m = flags.keyframe_cm / 100.0;
  p.motion.intervals.keyframe_rotation_rad = flags.keyframe_deg * std::numbers::pi / 180.0;
  p.motion.icp = flags.icp;
  p.motion.loop_closure = flags.loop_closure;
  p.exclude_disagreement = flags.exclude_disagreement;
  p.sync_clocks = flags.sync == "auto";
  p.mount_from_dataset = flags.lidar_mount == "dataset";
  mountPriorOf(flags, p);
  p.params.umbmark.side_m = flags.side_m;
  p.params.ceres.estimate_time_offset = flags.time_offset;
  p.params.joint.estimate_sideslip = flags.sideslip;  // ceres starts from joint's k
  p.params.ceres.estimate_sideslip = flags.sideslip;
  p.params.trim.enabled = flags.trim_sigmas > 0.0;
  if (p.params.trim.enabled) p.params.trim.threshold_sigmas = flags.trim_sigmas;
  p.nominal = nominalOf(flags);
  return recordings;
}

// Options that describe one recording: refused with several (docs/calibration.md).
void checkSeveral(const CalibrateFlags& flags) {
  const std::pair<const char*, bool> single[] = {{"--tuples", !flags.tuples_in.empty()},
                                                 {"--intervals", !flags.intervals_out.empty()},
                                                 {"--odometry-out", !flags.odometry_out.empty()},
                                                 {"--square", !flags.squares.empty()}};
  for (const auto& [option, given] : single)
    if (given)
      throw InputError(option,
                       "describes one recording; with several DATASETs run calibrate on each "
                       "(--tuples and --intervals: one recording's intervals; --odometry-out: "
                       "one recording's odometry; --square: the same square runs would count "
                       "once per recording)");
}

// Every output against every input (DATASETs, --square runs, --tuples) and each other.
void checkOutputs(const CalibrateFlags& flags) {
  OutputGuard guard(flags.force);
  for (const std::string& dir : flags.datasets) guard.input(dir, "DATASET");
  for (const std::string& dir : flags.squares) guard.input(dir, "--square");
  guard.input(flags.tuples_in, "--tuples");
  for (const auto& [file, option] : {std::pair{flags.json_out, "--json"},
                                     {flags.intervals_out, "--intervals"},
                                     {flags.odometry_out, "--odometry-out"},
                                     {flags.ros2_out, "--ros2-params"}})
    if (!file.empty()) guard.file(file, option);
  guard.check();
}

void checkPaths(const CalibrateFlags& flags) {
  const bool dataset = !flags.datasets.empty();
  for (const std::string& dir : flags.datasets) checkInputDataset(dir, "DATASET");
  if (flags.datasets.size() > 1) checkSeveral(flags);
  if (!flags.tuples_in.empty()) checkInputFile(flags.tuples_in, "--tuples");
  for (const std::string& dir : flags.squares) checkInputDataset(dir, "--square");
  checkOutputs(flags);
  if ((!flags.odometry_out.empty() || !flags.ros2_out.empty()) && !dataset)
    throw InputError("--odometry-out/--ros2-params", "need DATASET (its encoders and mount)");
  if (flags.loop_closure && (flags.motion != "icp" || !flags.tuples_in.empty()))
    throw InputError("--loop-closure",
                     "closes the loops of scan-matched motion: needs --motion icp, not --tuples");
  if (flags.validate_fraction != 0.0 &&
      (!(flags.validate_fraction > 0.0 && flags.validate_fraction < 1.0) || !dataset ||
       !flags.tuples_in.empty()))
    throw InputError("--validate-fraction",
                     "needs 0 < F < 1 and DATASET's scans (not --tuples): the last F of each "
                     "recording's scans are held out");
  if (flags.leave_one_out && (flags.datasets.size() < 2 || !flags.tuples_in.empty()))
    throw InputError("--leave-one-out",
                     "needs two or more DATASETs (not --tuples): each recording is scored with "
                     "the others' combined estimate");
  eval::checkSameNominal(flags.datasets, nominalOf(flags));
}

// --odometry-out and --ros2-params from the best of `runs` (one recording's, or the combined
// ones; `c`: the (first) recording, for its encoders, nominal geometry and mount); an error when
// no method is ok.
void writeBestOutputs(const CalibrateFlags& flags, const std::vector<algo::CalibrationRun>& runs,
                      const eval::DatasetCalibration& c) {
  if (flags.odometry_out.empty() && flags.ros2_out.empty()) return;
  const algo::CalibrationRun* best = algo::bestRun(runs);
  if (!best) throw InputError(flags.datasets.front(), "no method gave a result: nothing to write");
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

// Every line of `text` with `who` before it.
std::string prefixed(const std::string& text, const std::string& who) {
  std::string out;
  std::size_t start = 0;
  while (start < text.size()) {
    const std::size_t end = text.find('\n', start);
    out += who + text.substr(start, end - start) + "\n";
    if (end == std::string::npos) break;
    start = end + 1;
  }
  return out;
}

// What one recording's calibration found beside the estimates (stderr); `who` prefixes it.
void printNotes(const eval::DatasetCalibration& c, const std::string& who) {
  std::cerr << algo::stampsSummary(c.stamps);
  if (c.failed_matches > 0)
    std::cerr << who << c.failed_matches << " scan matches failed (chains broken)"
              << (c.sparse_scans > 0 ? ", " + std::to_string(c.sparse_scans) +
                                           " of them on scans with too few points for ICP "
                                           "(the lidar saw little)"
                                     : std::string())
              << "\n";
  if (c.from_motion)
    std::cerr << who << c.intervals.intervals.size() << " intervals ("
              << c.intervals.dropped_standstill << " standing still, "
              << c.intervals.dropped_uncovered << " without encoder data dropped)\n";
  if (c.loops)
    std::cerr << who << "loop closure: " << c.loops->used << " of " << c.loops->candidates
              << " direct matches used; largest heading change of one link "
              << c.loops->max_link_change_rad * 180.0 / std::numbers::pi * 1e3 << " mdeg\n";
  if (c.agreement) std::cerr << prefixed(algo::agreementText(*c.agreement), who);
  if (c.clock_offset_s != 0.0)
    std::cerr << who << "the scans lag the wheels by " << c.clock_offset_s
              << " s (sensor agreement, refined after matching again): the wheels' stamps "
                 "moved onto the scans' clock and the scans matched again before the intervals "
                 "were cut (--sync none keeps them)\n";
  if (c.intervals_excluded > 0)
    std::cerr << who << c.intervals_excluded
              << " intervals overlapping spans where the wheels and the "
              << (c.agreement && c.agreement->pair("wheels", "gyro") ? "gyro" : "scans")
              << " disagree left out (--exclude-disagreement)\n";
  for (const algo::CalibrationRun& run : c.runs) {
    if (run.time_offset_s)
      std::cerr << who << "ceres time offset " << *run.time_offset_s * 1e3 << " ms +- "
                << run.time_offset_sigma_s * 1e3 << " ms\n";
    if (run.sideslip_s)
      std::cerr << who << algo::calibrationMethodName(run.method) << " sideslip k "
                << *run.sideslip_s * 1e3 << " ms +- " << run.sideslip_sigma_s * 1e3
                << " ms (sideways speed k v w)\n";
  }
}

// One recording: today's table, then flags and the held-out validation.
void printOne(const eval::RecordingsCalibration& r) {
  const eval::DatasetCalibration& c = r.recordings.front().calibration;
  const std::vector<algo::MethodReport>& methods = r.report.recordings.front().methods;
  printTable(c.runs, c.truth);
  for (const eval::NotApplicable& n : c.not_applicable)
    std::cout << "\n"
              << algo::calibrationMethodName(n.method) << ": not applicable: " << n.reason << "\n";
  if (c.relative_to_odometry)
    std::cout << "\nrelative to the log's odometry: "
              << algo::odometryRelativeMeaning(*c.relative_to_odometry) << "\n";
  printAgainstNominal(methods, "", "the recording shows");
  printValidation(methods, "");
  printFlags(methods, "");
}

// Several recordings: compact tables, the combination, flags and validation of both.
void printSeveral(const eval::RecordingsCalibration& r) {
  printRecordings(r);
  for (std::size_t i = 0; i < r.recordings.size(); ++i) {
    const std::string label = "recording " + std::to_string(i + 1) + " ";
    printAgainstNominal(r.report.recordings[i].methods, "of " + label, "the recording shows");
    printValidation(r.report.recordings[i].methods, "of " + label);
    printFlags(r.report.recordings[i].methods, label);
  }
  printAgainstNominal(r.report.combined, "of the combined estimate ", "the recordings show");
  printValidation(r.report.combined, "of the combined estimate, mean over the recordings ");
  printFlags(r.report.combined, "combined ");
  printLeaveOneOut(r.report.leave_one_out);
}

// Exit 3 when every method refused (several recordings: every combined one), or with --strict
// when any run refused or any estimate was flagged.
int exitCode(const eval::RecordingsCalibration& r, bool strict) {
  bool any_refused = false, any_flagged = false;
  const auto scan = [&](const std::vector<algo::MethodReport>& methods) {
    for (const algo::MethodReport& m : methods) {
      any_refused = any_refused || !m.run.result.ok;
      any_flagged = any_flagged || !m.flags.empty();
    }
  };
  for (const algo::RecordingReport& rec : r.report.recordings) scan(rec.methods);
  scan(r.report.combined);
  const auto& decisive =
      r.recordings.size() > 1 ? r.report.combined : r.report.recordings.front().methods;
  const bool none_ok = std::none_of(decisive.begin(), decisive.end(),
                                    [](const algo::MethodReport& m) { return m.run.result.ok; });
  return refusalExitCode(none_ok, any_refused || any_flagged, strict);
}

int runCalibrate(const CalibrateFlags& flags) {
  checkPaths(flags);
  const std::size_t n = std::max<std::size_t>(1, flags.datasets.size());
  const eval::RecordingsCalibration r = [&] {
    CommandProgress progress(n, "recordings", "calibrate", !flags.quiet);
    StageReporter stages(flags.datasets.empty() ? "calibrate" : flags.datasets.front(), 1);
    stages.begin("calibrate");
    return eval::calibrateRecordings(paramsOf(flags),
                                     [&](const std::string& done) { progress.advance(done); });
  }();
  const bool several = r.recordings.size() > 1;
  for (const eval::RecordingCalibration& rec : r.recordings) {
    const std::string who = several ? "calibrate: " + rec.dataset + ": " : "calibrate: ";
    printNotes(rec.calibration, who);
    if (!rec.validation_note.empty()) std::cerr << who << rec.validation_note << "\n";
  }
  const eval::DatasetCalibration& first = r.recordings.front().calibration;
  if (!flags.intervals_out.empty())
    algo::writeIntervalRecords(flags.intervals_out, first.intervals.intervals);
  if (several)
    printSeveral(r);
  else
    printOne(r);
  if (!flags.json_out.empty()) algo::writeCalibrateJson(flags.json_out, r.report);
  std::vector<algo::CalibrationRun> combined;
  for (const algo::CombinedRun& c : r.combined) combined.push_back(c.run);
  writeBestOutputs(flags, several ? combined : first.runs, first);
  return exitCode(r, flags.strict);
}

}  // namespace

namespace {

/// The footer, the datasets, and where the motion comes from (methods, motion, stamps, de-skew).
void addCalibrateSources(CLI::App* cli, CalibrateFlags& flags) {
  cli->footer(
      "r_L, r_R, b (and the lidar mount) from wheel encoders plus the lidar's motion\n"
      "(docs/calibration.md). --method all runs the methods that apply to the data; one that\n"
      "does not (umbmark without square runs) is reported as not applicable.\n"
      "Several DATASETs: recordings of one robot (same nominal geometry, or --nominal), each\n"
      "calibrated on its own, then combined per method (information-weighted) with chi2/dof per\n"
      "parameter; where chi2/dof > 2 the recordings disagree beyond their sigmas: the combined\n"
      "sigma is scaled by sqrt(chi2/dof) and a WARNING names the worst recording. The same for\n"
      "r_L/b and r_R/b, what a drive pins down best: r and b can each agree while their ratio\n"
      "does not (WARNING: the recordings disagree on how far the robot turns per wheel turn).\n"
      "--json then writes {\"recordings\", \"combined\", \"consistency\"}; --ros2-params the\n"
      "combined best method; --tuples, --intervals, --odometry-out and --square are refused\n"
      "(exit 2).\n"
      "An estimate more than 15 % from the nominal r_L, r_R or b is flagged (FLAG line, JSON\n"
      "\"flags\") with its likely cause; so is a calibrated lidar mount more than 5 cm or 5 deg\n"
      "from the one the recording gave (tf, --lidar-mount at import). Exit 3 when every\n"
      "method run refused (several DATASETs: every combined one), or with --strict when any\n"
      "did or any estimate is flagged.");
  cli->add_option("DATASET", flags.datasets,
                  "dataset directory; several: recordings of one robot, combined");
  std::vector<std::string> methods = algo::calibrationMethodNames();
  methods.emplace_back("all");
  cli->add_option("--method", flags.method,
                  "calibration method, or all: the ones that apply to the data")
      ->check(oneOf("method", methods))
      ->capture_default_str();
  cli->add_option("--motion", flags.motion,
                  "lidar motion from scan-to-map matching (map: what `match` tracks, without "
                  "fusing the odometry), from chained scan-to-scan ICP (icp: what the bench "
                  "suites use; needed by --loop-closure), or from ground truth (oracle)")
      ->check(oneOf("motion", namesOf(eval::kMotionSourceNames)))
      ->capture_default_str();
  cli->add_option("--stamps", flags.stamps,
                  "auto: match scans on stamps put back on their constant-rate grid where a "
                  "stream (encoders, odometry, IMU, scans) is measurably jittered "
                  "(docs/calibration.md, \"Jittered stamps\"); raw: as logged. Outputs keep "
                  "the log's stamps")
      ->check(oneOf("stamps", {"auto", "raw"}))
      ->capture_default_str();
  std::vector<std::string> deskews = {"auto"};
  for (const std::string& m : namesOf(algo::kDeskewMethodNames)) deskews.push_back(m);
  cli->add_option("--deskew", flags.deskew,
                  "with --motion map or icp: de-skew scans with this method before matching "
                  "them. auto: "
                  "imu when the log has one (independent of the wheel geometry being "
                  "calibrated), else odom-linear with the nominal geometry, none on instantaneous "
                  "scans (time_increment 0); none: raw scans, which motion distortion biases")
      ->check(oneOf("de-skew method", deskews))
      ->capture_default_str();
  cli->add_flag("--stamp-is-last-beam", flags.stamp_is_last_beam,
                "the scans' stamps mark their last beam, not their first");
}

/// Files read and written besides the datasets, the nominal geometry, and the checks of the fit.
void addCalibrateFilesAndChecks(CLI::App* cli, CalibrateFlags& flags) {
  cli->add_option("--intervals", flags.intervals_out,
                  "write the intervals used as Censi records (JSON lines) to FILE; one DATASET "
                  "only")
      ->check(outputPath());
  cli->add_option("--tuples", flags.tuples_in,
                  "run on Censi interval records instead (JSON objects, one or several per "
                  "line); one DATASET at most");
  addJson(cli, flags,
          "one object per method (what deskew and export read with --calibration); with "
          "several DATASETs an object of recordings, combined methods and consistency (those "
          "read its combined methods)");
  cli->add_option("--odometry-out", flags.odometry_out,
                  "write the odometry re-integrated with the best result's geometry to FILE "
                  "(TUM; score it with `slamprep score relations`); one DATASET only")
      ->check(outputPath());
  cli->add_option("--ros2-params", flags.ros2_out,
                  "write the best result (several DATASETs: the best combined one) as "
                  "ros2_control diff_drive_controller parameters and the base_link -> laser "
                  "static transform to FILE (ROS 2 parameter YAML)")
      ->check(outputPath());
  cli->add_option("--nominal", flags.nominal,
                  "r_L,r_R,b in metres: the geometry the odometry uses (default: dataset.json's); "
                  "a log without encoder ticks gets its wheel increments derived from its "
                  "odometry poses with it, and the estimates are relative to it");
  cli->add_option("--validate-fraction", flags.validate_fraction,
                  "0 < F < 1: calibrate on the first 1 - F of each recording's scans and report "
                  "the raw (nominal) and calibrated odometry's relative pose error over 10 s "
                  "windows of the last F against their scan-to-map matched trajectory (JSON "
                  "\"validation\")");
  cli->add_flag("--leave-one-out", flags.leave_one_out,
                "with several DATASETs: score every recording whole (relative pose error over 10 s "
                "windows against its scan-to-map matched trajectory) with the combination of the "
                "OTHER recordings' estimates, beside the raw geometry (JSON \"leave_one_out\")");
  cli->add_option("--trim-sigmas", flags.trim_sigmas,
                  "drop intervals whose residual against a first fit exceeds N robust (MAD) "
                  "sigmas, refit until the kept set repeats; 0: keep every interval")
      ->check(nonNegative())
      ->capture_default_str();
  addForce(cli, flags, "existing output files");
  addStrict(cli, flags, "when any method refused, not only all, or any estimate is flagged");
  addQuiet(cli, flags);
}

/// How intervals are cut and which terms the model estimates.
void addCalibrateModel(CLI::App* cli, CalibrateFlags& flags) {
  cli->add_option("--keyframe-cm", flags.keyframe_cm,
                  "new interval every N cm of lidar motion (0: every scan match, as the bench)")
      ->check(nonNegative())
      ->capture_default_str();
  cli->add_option("--keyframe-deg", flags.keyframe_deg, "... or every N degrees")
      ->check(nonNegative())
      ->capture_default_str();
  addIcpOptions(cli, flags.icp);
  cli->add_option("--square", flags.squares,
                  "UMBmark square-run dataset (repeatable); one DATASET at most");
  cli->add_option("--side", flags.side_m, "UMBmark square side (m)")
      ->check(positive())
      ->capture_default_str();
  cli->add_flag("--time-offset", flags.time_offset,
                "ceres: also estimate a constant encoder-to-lidar clock offset");
  cli->add_flag("--sideslip", flags.sideslip,
                "joint and ceres: also estimate a sideslip k, the base moving sideways at k v w in "
                "turns (not with --time-offset)")
      ->excludes("--time-offset");
  cli->add_flag("--loop-closure", flags.loop_closure,
                "with --motion icp: where the matched path revisits a place (10 s or more later, "
                "within 0.3 m and 20 deg) match the two scans directly and spread the heading "
                "drift this reveals back over the matches. Chained matches drift in heading, which "
                "reads as r_R != r_L and which no sigma of the same log can show");
  cli->add_option("--sync", flags.sync,
                  "auto: where the sensor agreement finds the scans lagging the wheels by more "
                  "than 20 ms, move the wheels' (and the gyro's) stamps onto the scans' clock, "
                  "match the scans again and move what delay is left, before cutting intervals; "
                  "none: the stamps as logged")
      ->check(oneOf("sync", {"auto", "none"}))
      ->capture_default_str();
  cli->add_option("--lidar-mount", flags.lidar_mount,
                  "what direct and model, which do not estimate a mount, take it as: centre (the "
                  "lecture's methods: the lidar at the robot centre) or dataset (the dataset's "
                  "mount, e.g. from tf, taken as known; for a lidar off the centre or turned, such "
                  "as one facing backwards). joint and ceres estimate it either way")
      ->check(oneOf("lidar-mount", {"centre", "dataset"}))
      ->capture_default_str();
  cli->add_option("--mount-prior", flags.mount_prior,
                  "CM,DEG: the mount the recording came with (a tf or --lidar-mount at import; "
                  "not a simulated dataset's) fused into joint and ceres as a prior with these "
                  "1-sigmas, unless the fit contradicts it (chi2 over 14.2: left alone, and "
                  "flagged lidar_mount); none: the intervals alone (docs/calibration.md, \"Mount "
                  "prior\")")
      ->capture_default_str();
  cli->add_flag("--exclude-disagreement", flags.exclude_disagreement,
                "where the wheels and the gyro disagree beyond any wheel geometry (a lifted or "
                "blocked robot, slip), calibrate on the intervals outside those spans instead of "
                "refusing (exit 3); without a gyro, leave out the spans where the wheels and the "
                "scans disagree (flagged wheels_vs_scans otherwise); the spans are printed either "
                "way (docs/calibration.md)");
}

}  // namespace

Command addCalibrateCommand(CLI::App& app) {
  auto flags = std::make_shared<CalibrateFlags>();
  auto* cli = app.add_subcommand("calibrate",
                                 "Odometry calibration: wheel radii, wheel base and lidar mount.");
  addCalibrateSources(cli, *flags);
  addCalibrateFilesAndChecks(cli, *flags);
  addCalibrateModel(cli, *flags);
  return {cli, [flags] { return runCalibrate(*flags); }};
}

}  // namespace slamprep::app
