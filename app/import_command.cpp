// `slamprep import`: a CARMEN log or an MCAP ROS 2 bag into a dataset directory (no ground
// truth) that calibrate and deskew read (docs/export.md).
#include <iostream>
#include <sstream>

#include "app/commands.hpp"
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
  std::string lidar_mount;  // "x,y,yaw"
  std::string nominal;      // "r_L,r_R,b"
  eval::ImportParams params;
};

SE2 parseMount(const std::string& text) {
  std::vector<std::string_view> fields;
  slamprep::eval::splitFields(text, ',', fields);
  if (fields.size() != 3) throw InputError("--lidar-mount", "expected x,y,yaw (m, m, rad)");
  const slamprep::eval::TextLocation where{"--lidar-mount", 0};
  return {slamprep::eval::parseFiniteDouble(fields[0], where, "x"),
          slamprep::eval::parseFiniteDouble(fields[1], where, "y"),
          slamprep::eval::parseFiniteDouble(fields[2], where, "yaw")};
}

DiffDriveParams parseNominal(const std::string& text) {
  std::vector<std::string_view> fields;
  slamprep::eval::splitFields(text, ',', fields);
  if (fields.size() != 3) throw InputError("--nominal", "expected r_L,r_R,b (m, m, m)");
  const slamprep::eval::TextLocation where{"--nominal", 0};
  return {slamprep::eval::parseFiniteDouble(fields[0], where, "r_L"),
          slamprep::eval::parseFiniteDouble(fields[1], where, "r_R"),
          slamprep::eval::parseFiniteDouble(fields[2], where, "b")};
}

int runImport(ImportFlags flags) {
  if (flags.wheel_radius_m > 0)
    flags.geometry.radius_left_m = flags.geometry.radius_right_m = flags.wheel_radius_m;
  if (flags.geometry_given) flags.params.nominal_geometry = flags.geometry;
  if (!flags.nominal.empty()) flags.params.nominal_geometry = parseNominal(flags.nominal);
  if (flags.time_increment_given) flags.params.time_increment_s = flags.time_increment_s;
  if (!flags.lidar_mount.empty()) flags.params.T_base_lidar = parseMount(flags.lidar_mount);
  // A bag is read chunk by chunk from its files; a CARMEN log is text read whole.
  const eval::ImportResult result =
      flags.format == "carmen"
          ? eval::importCarmen(slamprep::eval::readTextFile(flags.input), flags.input, flags.params)
          : eval::importMcap(std::filesystem::path(flags.input), flags.params);
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
      "import",
      "Read a CARMEN log or a ROS 2 bag (MCAP: a bag folder or one .mcap file; LaserScan + "
      "Odometry or JointState) into a dataset directory.");
  cli->add_option("--format", flags->format, "carmen|mcap")
      ->required()
      ->check(CLI::IsMember({"carmen", "mcap"}));
  cli->add_option("PATH", flags->input, "log file, bag folder (metadata.yaml) or .mcap file")
      ->required();
  cli->add_option("--out", flags->out, "dataset directory to write")->required();
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
  cli->add_option("--nominal", flags->nominal,
                  "nominal wheel geometry r_L,r_R,b (m); mcap: required unless the bag carries "
                  "it (slamprep exports do)");
  cli->add_option("--ticks-per-revolution", flags->params.ticks_per_revolution,
                  "resolution of the derived encoder ticks")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cli->add_option("--time-increment", flags->time_increment_s,
                  "time between beams (s); carmen default: the log's PARAM, else 0 = unknown "
                  "(de-skew refuses); mcap: replaces every LaserScan's")
      ->check(CLI::NonNegativeNumber)
      ->each([flags](const std::string&) { flags->time_increment_given = true; });
  cli->add_option("--lidar-mount", flags->lidar_mount,
                  "x,y,yaw of the lidar on the base (default: from the log (mcap: the tf tree), "
                  "else 0,0,0)");
  cli->add_option("--base-frame", flags->params.base_frame, "mcap: the robot's base frame in tf")
      ->capture_default_str();
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
