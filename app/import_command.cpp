// `slamprep import`: a CARMEN log or an MCAP ROS 2 bag into a dataset directory (no ground
// truth) that calibrate and deskew read (docs/export.md).
#include <iostream>
#include <numbers>
#include <sstream>

#include "app/choices.hpp"
#include "app/commands.hpp"
#include "app/outputs.hpp"
#include "core/error.hpp"
#include "eval/formats/dataset_io.hpp"
#include "eval/formats/import.hpp"
#include "eval/formats/text_io.hpp"

namespace slamprep::app {
namespace {

struct ImportFlags {
  std::string format;
  std::string input;
  std::string out;
  double wheel_radius_m = 0.0;  // 0: use the left/right ones
  DiffDriveParams geometry;
  double time_increment_s = 0.0;
  bool geometry_given = false;
  bool time_increment_given = false;
  std::string lidar_mount;  // "x,y,yaw_deg"
  eval::ImportParams params;
  bool force = false;
};

SE2 parseMount(const std::string& text) {
  std::vector<std::string_view> fields;
  slamprep::eval::splitFields(text, ',', fields);
  if (fields.size() != 3) throw InputError("--lidar-mount", "expected x,y,yaw_deg (m, m, deg)");
  const slamprep::eval::TextLocation where{"--lidar-mount", 0};
  const double yaw_deg = slamprep::eval::parseFiniteDouble(fields[2], where, "yaw_deg");
  return {slamprep::eval::parseFiniteDouble(fields[0], where, "x"),
          slamprep::eval::parseFiniteDouble(fields[1], where, "y"),
          yaw_deg * std::numbers::pi / 180.0};
}

int runImport(ImportFlags flags) {
  checkInputFile(flags.input, "PATH");
  checkOutputDataset(flags.out, "--out", flags.force);
  if (flags.wheel_radius_m > 0)
    flags.geometry.radius_left_m = flags.geometry.radius_right_m = flags.wheel_radius_m;
  if (flags.geometry_given) flags.params.nominal_geometry = flags.geometry;
  if (flags.time_increment_given) flags.params.time_increment_s = flags.time_increment_s;
  if (!flags.lidar_mount.empty()) flags.params.T_base_lidar = parseMount(flags.lidar_mount);
  const std::string bytes = slamprep::eval::readTextFile(flags.input);
  const eval::ImportResult result = flags.format == "carmen"
                                        ? eval::importCarmen(bytes, flags.input, flags.params)
                                        : eval::importMcap(bytes, flags.input, flags.params);
  eval::writeDataset(flags.out, result.dataset);
  const Dataset& d = result.dataset;
  std::cout << "imported " << d.scans.size() << " scans, " << d.encoders.size()
            << " encoder samples, " << d.odom_nominal.size() << " odometry poses, " << d.imu.size()
            << " IMU samples into " << flags.out << "\n";
  for (const auto& note : result.notes) std::cerr << "import: note: " << note << "\n";
  return 0;
}

}  // namespace

Command addImportCommand(CLI::App& app) {
  auto flags = std::make_shared<ImportFlags>();
  auto* cli = app.add_subcommand(
      "import", "Read a CARMEN log or an MCAP ROS 2 bag into a dataset directory.");
  cli->footer(
      "An MCAP bag needs a LaserScan topic plus Odometry or JointState (docs/export.md). The\n"
      "dataset has no ground truth; calibrate, deskew, match and export read it.");
  cli->add_option("--format", flags->format, "carmen|mcap")
      ->required()
      ->check(oneOf("format", {"carmen", "mcap"}));
  cli->add_option("PATH", flags->input, "log file")->required();
  cli->add_option("--out", flags->out,
                  "dataset directory to write; an existing one is refused unless --force")
      ->required();
  cli->add_flag("--force", flags->force,
                "replace an existing --out dataset; the old one stays until the new is complete");
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
      ->check(CLI::PositiveNumber);
  cli->add_option("--wheel-radius-left", g.radius_left_m, "nominal left wheel radius (m)")
      ->check(CLI::PositiveNumber)
      ->each(given)
      ->capture_default_str();
  cli->add_option("--wheel-radius-right", g.radius_right_m, "nominal right wheel radius (m)")
      ->check(CLI::PositiveNumber)
      ->each(given)
      ->capture_default_str();
  cli->add_option("--wheel-base", g.wheel_base_m, "nominal wheel base (m)")
      ->check(CLI::PositiveNumber)
      ->each(given)
      ->capture_default_str();
  cli->add_option("--ticks-per-revolution", flags->params.ticks_per_revolution,
                  "resolution of the derived encoder ticks")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cli->add_option("--time-increment", flags->time_increment_s,
                  "carmen: time between beams (s); default: the log's PARAM, else 0 = unknown "
                  "(de-skew refuses)")
      ->check(CLI::NonNegativeNumber)
      ->each([flags](const std::string&) { flags->time_increment_given = true; });
  cli->add_option("--lidar-mount", flags->lidar_mount,
                  "x,y,yaw_deg of the lidar on the base: metres, metres, degrees (default: from "
                  "the log, else 0,0,0)");
  cli->add_flag("--trim", flags->params.trim, "drop scans the odometry does not cover");
  cli->add_option("--scan-topic", flags->params.scan_topic, "mcap: LaserScan topic");
  cli->add_option("--odom-topic", flags->params.odom_topic, "mcap: Odometry topic");
  cli->add_option("--joint-topic", flags->params.joint_topic, "mcap: JointState topic");
  cli->add_option("--imu-topic", flags->params.imu_topic, "mcap: Imu topic");
  cli->add_option("--left-joint", flags->params.left_joint, "mcap: left wheel joint name");
  cli->add_option("--right-joint", flags->params.right_joint, "mcap: right wheel joint name");
  return {cli, [flags] { return runImport(*flags); }};
}

}  // namespace slamprep::app
