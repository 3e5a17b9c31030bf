// `slamprep import`: a CARMEN log or a ROS 2 bag (sqlite3 or MCAP) into a dataset directory (no
// ground truth) that calibrate and deskew read (docs/export.md).
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <numbers>
#include <sstream>

#include "slamprep/algo/agreement/agreement_report.hpp"
#include "slamprep/algo/agreement/dataset_sources.hpp"
#include "slamprep/app/choices.hpp"
#include "slamprep/app/commands.hpp"
#include "slamprep/app/common_flags.hpp"
#include "slamprep/app/outputs.hpp"
#include "slamprep/core/atomic_file.hpp"
#include "slamprep/core/error.hpp"
#include "slamprep/eval/formats/dataset_io.hpp"
#include "slamprep/eval/formats/import.hpp"
#include "slamprep/eval/formats/import_json.hpp"
#include "slamprep/eval/formats/text_io.hpp"

namespace slamprep::app {
namespace {

struct ImportFlags : CommonFlags {
  std::string format;
  std::string input;
  std::string out;
  double wheel_radius_m = 0.0;  // 0: use the left/right ones
  DiffDriveParams geometry;
  std::string time_increment;  // --time-increment: seconds, or "auto"
  bool geometry_given = false;
  bool time_increment_given = false;
  std::string lidar_mount;  // "x,y,yaw_deg"
  std::string nominal;      // "r_L,r_R,b"
  bool no_trim = false;     // --no-trim: refuse scans the odometry does not cover
  eval::ImportParams params;
};

/// --lidar-mount x,y,yaw: metres and degrees on the command line.
SE2 parseMount(const std::string& text) {
  const auto v = parseList(text, "--lidar-mount", {"x", "y", "yaw_deg"});
  return {v[0], v[1], v[2] * std::numbers::pi / 180};
}

/// --time-increment SECONDS (>= 0), or `auto` for bags (eval::ImportParams).
void setTimeIncrement(const std::string& text, bool carmen, eval::ImportParams& params) {
  if (text == "auto") {
    if (carmen)
      throw InputError("--time-increment",
                       "auto is for bags, whose scans carry their own "
                       "(give the laser's SECONDS for a CARMEN log)");
    params.time_increment_one_turn = true;
    return;
  }
  char* end = nullptr;
  const double seconds = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !std::isfinite(seconds))
    throw InputError("--time-increment", "expected seconds or auto (got " + text + ")");
  if (seconds < 0.0) throw InputError("--time-increment", "must be >= 0 (got " + text + ")");
  params.time_increment_s = seconds;
}

void printSummary(const eval::ImportSummary& s, bool carmen) {
  const auto row = [](const char* what, const std::string& text) {
    if (!text.empty()) std::cout << "  " << what << text << "\n";
  };
  row("storage:          ", s.storage);
  for (const auto& [type, topic] : s.topics) row("topic:            ", topic + " (" + type + ")");
  row("scans:            ", s.scans);
  row("odometry:         ", s.odometry);
  row("lidar mount:      ", s.lidar_mount);
  row("nominal geometry: ", s.nominal_geometry);
  row("time increment:   ", s.time_increment);
  if (s.range) row("max range:        ", s.range->text());
  for (const auto& stale : s.stale) row("stale odometry:   ", stale.text());
  if (s.twist_spikes) row("twist spikes:     ", s.twist_spikes->text());
  if (!carmen || s.scans.empty()) return;
  std::string reordered;
  for (const auto& [what, n] : s.reordered)
    reordered += (reordered.empty() ? "" : ", ") + std::to_string(n) + " " + what;
  row("reordered stamps: ",
      reordered.empty() ? "none" : reordered + " lines not at their sorted position, sorted");
  if (s.dropped.empty()) row("dropped lines:    ", "none");
  for (const auto& [why, n] : s.dropped) row("dropped lines:    ", std::to_string(n) + " " + why);
}

int runImport(ImportFlags flags) {
  const bool carmen = flags.format == "carmen";
  // A ROS 2 bag may be a folder (metadata.yaml + storage files); everything else is one file.
  if (carmen || !std::filesystem::is_directory(flags.input)) checkInputFile(flags.input, "PATH");
  OutputGuard guard(flags.force);
  guard.input(flags.input, "PATH").dataset(flags.out, "--out");
  if (!flags.json_out.empty()) guard.file(flags.json_out, "--json");
  guard.check();
  if (flags.wheel_radius_m > 0)
    flags.geometry.radius_left_m = flags.geometry.radius_right_m = flags.wheel_radius_m;
  if (flags.geometry_given) flags.params.nominal_geometry = flags.geometry;
  flags.params.trim = !flags.no_trim;
  if (flags.time_increment_given) setTimeIncrement(flags.time_increment, carmen, flags.params);
  if (!flags.lidar_mount.empty()) flags.params.T_base_lidar = parseMount(flags.lidar_mount);
  if (!flags.nominal.empty()) {
    if (flags.geometry_given)
      throw InputError("--nominal", "give either --nominal or the --wheel-* flags, not both");
    const auto v = parseList(flags.nominal, "--nominal", {"r_L", "r_R", "b"});
    flags.params.nominal_geometry = DiffDriveParams{v[0], v[1], v[2]};
  }
  // A CARMEN log is text read whole. A bag is read chunk by chunk from its files, its scans
  // parked in a spill file inside the dataset being written and streamed into scans.jsonl, so
  // memory holds the small streams, not the ranges.
  eval::ImportResult result;
  std::size_t scans = 0;
  if (carmen) {
    result = eval::importCarmen(eval::readTextFile(flags.input), flags.input, flags.params);
    eval::writeDataset(flags.out, result.dataset);
    scans = result.dataset.scans.size();
  } else {
    eval::publishDirectoryAtomically(flags.out, [&](const std::filesystem::path& partial) {
      flags.params.spill_dir = partial;
      result = eval::importRosbag2(std::filesystem::path(flags.input), flags.params);
      eval::writeDatasetFiles(partial, result.dataset, flags.out,
                              [&](ScanRecord& r) { return result.scans->next(r); });
      scans = result.scans->count();
      for (std::string& note : result.scans->notes()) result.notes.push_back(std::move(note));
      result.scans.reset();  // deletes the spill file before the directory is published
    });
  }
  const Dataset& d = result.dataset;
  std::cout << "imported " << scans << " scans, " << d.encoders.size() << " encoder samples, "
            << d.odom_nominal.size() << " odometry poses, " << d.imu.size() << " IMU samples into "
            << flags.out << "\n";
  printSummary(result.summary, carmen);
  for (const auto& note : result.notes) std::cerr << "import: note: " << note << "\n";
  // Wheels, gyro and the odometry topic, whichever the log has (the scans: `match`).
  const algo::SensorAgreement agreement = algo::compareSensors(algo::datasetSources(d));
  std::cout << algo::agreementText(agreement);
  if (!flags.json_out.empty()) {
    auto json = eval::importSummaryJson(flags.input, flags.format, flags.out, result.summary, d,
                                        {scans}, result.notes);
    json["sensor_agreement"] = algo::agreementJson(agreement, algo::encodersFrom(d.info));
    writeFileAtomic(flags.json_out, json.dump(2) + "\n");
  }
  return 0;
}

}  // namespace

namespace {

/// The footer, the log and the dataset written, and how scans are read.
void addImportInOut(CLI::App* cli, const std::shared_ptr<ImportFlags>& flags) {
  cli->footer(
      "A bag needs a LaserScan topic plus Odometry or JointState (docs/export.md); --format mcap\n"
      "and rosbag2 read the same (any storage). The dataset has no ground truth; calibrate,\n"
      "deskew, match and export read it.");
  cli->add_option("--format", flags->format, "carmen|mcap|rosbag2")
      ->required()
      ->check(oneOf("format", {"carmen", "mcap", "rosbag2"}));
  cli->add_option("PATH", flags->input,
                  "log file, bag folder (metadata.yaml), or one .db3 or .mcap file")
      ->required();
  cli->add_option("--out", flags->out,
                  "dataset directory to write; an existing one is refused unless --force")
      ->required()
      ->check(outputPath());
  addForce(cli, *flags, "an existing --out dataset (and --json file)");
  addJson(cli, *flags, "what the import read and decided (docs/export.md)");
  cli->add_option_function<double>(
         "--max-range", [flags](double m) { flags->params.max_range_m = m; },
         "readings beyond this (m) become no return and range_max is set to it (default: the "
         "scans' range_max, with a note when it is over twice the 99.9th percentile reading)")
      ->check(positive());
  cli->add_flag("--reverse-beam-time", flags->params.reverse_beam_time,
                "bags: the beams were taken in the reverse of their array order (an RPLIDAR under "
                "its ROS driver): each scan is reversed so that it runs in time order");
}

/// The geometry the odometry used, the encoders and the lidar's timing and mount.
void addImportGeometry(CLI::App* cli, const std::shared_ptr<ImportFlags>& flags) {
  // The nominal geometry: any of these flags replaces the log's (CARMEN PARAM lines) or the
  // default; the ones not given keep the default.
  auto& g = flags->geometry;
  auto given = [flags](auto) { flags->geometry_given = true; };
  cli->add_option_function<double>(
         "--wheel-radius",
         [flags](double r) {
           flags->wheel_radius_m = r;
           flags->geometry_given = true;
         },
         "nominal radius of both wheels (m)")
      ->check(positive());
  cli->add_option("--wheel-radius-left", g.radius_left_m, "nominal left wheel radius (m)")
      ->check(positive())
      ->each(given)
      ->capture_default_str();
  cli->add_option("--wheel-radius-right", g.radius_right_m, "nominal right wheel radius (m)")
      ->check(positive())
      ->each(given)
      ->capture_default_str();
  cli->add_option("--wheel-base", g.wheel_base_m, "nominal wheel base (m)")
      ->check(positive())
      ->each(given)
      ->capture_default_str();
  cli->add_option("--nominal", flags->nominal,
                  "nominal wheel geometry r_L,r_R,b (m); bags: required unless the bag carries "
                  "it (slamprep exports do)");
  cli->add_option("--ticks-per-revolution", flags->params.ticks_per_revolution,
                  "resolution of the derived encoder ticks")
      ->check(positive())
      ->capture_default_str();
  cli->add_option("--time-increment", flags->time_increment,
                  "time between beams (s); carmen default: the log's PARAM, else 0 = unknown "
                  "(de-skew refuses); bags: replace every LaserScan's, or `auto`: give a scan "
                  "with 0 the time of a head that turns once per scan (its median period x "
                  "|angle_increment| / 2 pi)")
      ->each([flags](const std::string&) { flags->time_increment_given = true; });
  cli->add_option("--lidar-mount", flags->lidar_mount,
                  "x,y,yaw_deg of the lidar on the base: metres, metres, degrees (default: from "
                  "the log: bags' tf tree, CARMEN's PARAM lines or the one offset every laser "
                  "line has between robot and laser pose; else 0,0,0)");
  cli->add_flag("--lidar-mount-from-poses", flags->params.lidar_mount_from_poses,
                "carmen: without --lidar-mount or a mount PARAM, take robot_pose^-1 laser_pose "
                "of the first line even where the lines' offsets differ");
}

/// What a CARMEN log or a bag holds where: stamps, lasers, topics, frames, joints.
void addImportSources(CLI::App* cli, const std::shared_ptr<ImportFlags>& flags) {
  cli->add_option("--reorder-tolerance", flags->params.reorder_tolerance_s,
                  "carmen: stamps running backwards by up to this (s) are sorted into place")
      ->check(nonNegative())
      ->capture_default_str();
  cli->add_option_function<std::string>(
         "--out-of-order",
         [flags](const std::string& v) { flags->params.drop_late_stamps = v == "drop"; },
         "carmen: sort (stamps out of order within the tolerance are sorted) or drop (lines "
         "stamped after a later line are dropped, file order kept)")
      ->check(oneOf("out-of-order mode", {"sort", "drop"}));
  cli->add_option("--laser", flags->params.laser,
                  "carmen: ROBOTLASER1|FLASER|RLASER|RAWLASER1..4 (default: the first present)");
  cli->add_option("--odometry", flags->params.odometry,
                  "carmen: odom (ODOM lines) or laser (the laser lines' robot poses); default: "
                  "ODOM when present")
      ->check(oneOf("odometry source", {"odom", "laser"}));
  cli->add_option("--base-frame", flags->params.base_frame, "bags: the robot's base frame in tf")
      ->capture_default_str();
  // No variable: --trim is the default, accepted for scripts that pass it (a const description
  // is CLI11's flag without one).
  const std::string trim_help =
      "drop the scans the odometry does not cover, before its first sample or after its last (the "
      "default: topics start and stop at different times; the note says how many)";
  cli->add_flag("--trim", trim_help);
  cli->add_flag("--no-trim", flags->no_trim,
                "refuse a log with scans the odometry does not cover, naming the first such scan")
      ->excludes("--trim");
  cli->add_option("--scan-topic", flags->params.scan_topic, "bags: LaserScan topic");
  cli->add_option("--odom-topic", flags->params.odom_topic, "bags: Odometry topic");
  cli->add_option("--joint-topic", flags->params.joint_topic, "bags: JointState topic");
  cli->add_option("--imu-topic", flags->params.imu_topic, "bags: Imu topic");
  cli->add_option("--left-joint", flags->params.left_joint, "bags: left wheel joint name");
  cli->add_option("--right-joint", flags->params.right_joint, "bags: right wheel joint name");
}

}  // namespace

Command addImportCommand(CLI::App& app) {
  auto flags = std::make_shared<ImportFlags>();
  auto* cli = app.add_subcommand(
      "import",
      "Read a CARMEN log or a ROS 2 bag (a bag folder, sqlite3 or MCAP storage, or one .db3 or "
      ".mcap file; LaserScan + Odometry or JointState) into a dataset directory.");
  addImportInOut(cli, flags);
  addImportGeometry(cli, flags);
  addImportSources(cli, flags);
  return {cli, [flags] { return runImport(*flags); }};
}

}  // namespace slamprep::app
