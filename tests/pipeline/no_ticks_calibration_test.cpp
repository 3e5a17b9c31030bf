// Calibration of a log with odometry poses but no encoder ticks (the committed CARMEN excerpts
// imported without --nominal): wheel increments derived from the poses, estimates relative to the
// log's odometry geometry; and the --ros2-params file read back with yaml-cpp.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <filesystem>

#include "slamprep/algo/calibration/calibration_json.hpp"
#include "slamprep/core/atomic_file.hpp"
#include "slamprep/core/error.hpp"
#include "slamprep/eval/formats/dataset_io.hpp"
#include "slamprep/eval/formats/export.hpp"
#include "slamprep/eval/formats/import.hpp"
#include "slamprep/eval/formats/ros2_params.hpp"
#include "slamprep/eval/formats/tum.hpp"
#include "slamprep/eval/pipeline/calibration_run.hpp"
#include "slamprep/tests/support/scratch_dir.hpp"

namespace slamprep::eval {
namespace {

namespace fs = std::filesystem;

// The excerpt imported as `slamprep import --format carmen` would, without a nominal geometry,
// into a folder of `scratch`.
fs::path importExcerpt(const test::ScratchDir& scratch, const std::string& name,
                       const std::string& odometry) {
  const std::string file = std::string(SLAMPREP_SOURCE_DIR) + "/tests/data/" + name;
  ImportParams params;
  params.odometry = odometry;
  params.reorder_tolerance_s = 1.0;
  const ImportResult imported = importCarmen(readFile(file), file, params);
  EXPECT_TRUE(imported.dataset.encoders.empty());
  const fs::path dir = scratch / ("no_ticks_" + odometry);
  writeDataset(dir, imported.dataset);
  return dir;
}

class NoTicks : public ::testing::TestWithParam<std::pair<const char*, const char*>> {};

TEST_P(NoTicks, CalibratesRelativeToTheLogsOdometry) {
  const test::ScratchDir scratch("no_ticks");
  const fs::path dir = importExcerpt(scratch, GetParam().first, GetParam().second);
  DatasetCalibrationParams params;
  params.dataset = dir.string();
  params.methods = algo::intervalMethods();
  const DatasetCalibration c = calibrateDataset(params);
  // Without --nominal: dataset.json's placeholder geometry, stated on every run.
  ASSERT_TRUE(c.relative_to_odometry);
  EXPECT_EQ(c.relative_to_odometry->wheel_base_m, DiffDriveParams{}.wheel_base_m);
  EXPECT_GT(c.intervals.intervals.size(), 100u);
  for (const algo::CalibrationRun& run : c.runs) {
    ASSERT_TRUE(run.relative_to_odometry);
    if (!algo::estimatesMount(run.method)) continue;
    ASSERT_TRUE(run.result.ok) << run.result.reason;
    // The log's odometry is close to right: scale factors within 10 % of 1.
    const DiffDriveParams& g = run.result.geometry;
    EXPECT_NEAR(g.radius_left_m / c.relative_to_odometry->radius_left_m, 1.0, 0.1);
    EXPECT_NEAR(g.radius_right_m / c.relative_to_odometry->radius_right_m, 1.0, 0.1);
    EXPECT_NEAR(g.wheel_base_m / c.relative_to_odometry->wheel_base_m, 1.0, 0.1);
  }
  const std::string json = algo::formatCalibrationJson(c.runs, std::nullopt);
  EXPECT_NE(json.find("\"relative_to_odometry\""), std::string::npos);
  EXPECT_NE(json.find("\"scale\""), std::string::npos);

  // Re-integrating the derived increments with the nominal geometry gives the log's odometry up
  // to the sideways steps no wheel motion explains, which the derivation drops (measured: 6.6 cm
  // over Intel's 30 m, 3.0 cm over ACES's excerpt).
  const PoseSeries again = calibratedOdometry(c, *c.relative_to_odometry);
  const Dataset d = readDataset(dir);
  ASSERT_EQ(again.size(), d.odom_nominal.size());
  double worst = 0.0;
  for (std::size_t i = 0; i < again.size(); ++i)
    worst = std::max(worst,
                     (again[i].value.translation() - d.odom_nominal[i].value.translation()).norm());
  EXPECT_LT(worst, 0.1);
}

// The calibration's scan matcher takes the same ICP settings as `match` (`calibrate
// --line-thickness` ...): on ACES' 180-beam scans the library's 0.2-thick line fits leave most
// consecutive matches failed, 0.5 few of them (measured: 467 and 73 of the 739 matches).
TEST(NoTicksIcp, LineThicknessReachesTheCalibrationsScanMatcher) {
  const test::ScratchDir scratch("no_ticks");
  const fs::path dir = importExcerpt(scratch, "carmen_aces/aces_first120s.clf", "odom");
  const Dataset dataset = readDataset(dir);
  CalibrationMotionOptions options;
  const int failed_thin = calibrationMotion(dataset, options).failed_matches;
  options.icp.line_max_thickness = 0.5;
  const int failed_thick = calibrationMotion(dataset, options).failed_matches;
  EXPECT_GT(failed_thin, 300);
  EXPECT_LT(failed_thick, 150);
}

INSTANTIATE_TEST_SUITE_P(CarmenExcerpts, NoTicks,
                         ::testing::Values(std::pair{"carmen_intel/intel_first180s.clf", "laser"},
                                           std::pair{"carmen_aces/aces_first120s.clf", "odom"}),
                         [](const auto& info) {
                           return std::string(info.param.second == std::string("laser") ? "intel"
                                                                                        : "aces");
                         });

// `export --format tum --calibration CAL.json` on a log without ticks wrote an empty
// odom_calibrated.tum: it integrated the (absent) ticks. It now writes what `calibrate
// --odometry-out` writes (one function, eval/formats/wheel_odometry.hpp), increments derived with
// the calibration's relative_to_odometry; and refuses, not writes nothing, without odometry.
TEST(NoTicksExport, WritesTheCalibratedOdometryCalibrateWrites) {
  const test::ScratchDir scratch("no_ticks_export");
  const fs::path dir = importExcerpt(scratch, "carmen_intel/intel_first180s.clf", "laser");
  const fs::path tuples = scratch / "one.tuple";  // no scan matching needed for the odometry
  writeFileAtomic(tuples, "{\"T\": 1, \"phi_l\": 1, \"phi_r\": 1, \"sm\": [0.1, 0, 0]}\n");
  DatasetCalibrationParams params;
  params.dataset = dir.string();
  params.tuples = tuples.string();
  params.methods = {algo::CalibrationMethod::kModel};
  const DatasetCalibration c = calibrateDataset(params);
  ASSERT_TRUE(c.relative_to_odometry);
  algo::CalibrationRun run;  // what calibrate --json would hold for a calibrated geometry
  run.method = algo::CalibrationMethod::kModel;
  run.result.ok = true;
  run.result.geometry = {0.101, 0.0985, 0.52};
  run.relative_to_odometry = c.relative_to_odometry;
  const std::string odometry_out = formatTum(calibratedOdometry(c, run.result.geometry), "odom");

  ExportInput input = loadExportInput(dir);
  const algo::CalibrationRun best =
      algo::parseCalibrationJson(algo::formatCalibrationJson({run}, std::nullopt), "cal.json")
          .requireBest();
  input.calibration = CalibrationChoice{best.result.geometry, "model", best.relative_to_odometry};
  const fs::path out = scratch / "tum";
  fs::create_directories(out);
  const ExportResult result = exportDataset(input, ExportFormat::kTum, out);
  EXPECT_GT(result.counts.at("odom_calibrated"), 900u);  // 912 odometry poses in 180 s
  EXPECT_EQ(readFile(out / "odom_calibrated.tum"), odometry_out);

  input.dataset.odom_nominal = PoseSeries();  // nothing to integrate: an error, not a file
  EXPECT_THROW(calibratedOdometry(input), InputError);
}

TEST(Ros2Params, ReadsBackAsTheCalibratedGeometryAndMount) {
  Ros2ParamsInput in;
  in.nominal = {0.1, 0.1, 0.5};
  in.calibrated = {0.0981, 0.1013, 0.5234};
  in.T_base_lidar = SE2(0.12, -0.04, 0.3);
  in.method = "ceres";
  in.mount_calibrated = true;
  const YAML::Node root = YAML::Load(formatRos2Params(in));
  const YAML::Node p = root["diff_drive_controller"]["ros__parameters"];
  const double radius = p["wheel_radius"].as<double>();
  EXPECT_EQ(radius, 0.1);
  EXPECT_EQ(p["wheel_separation"].as<double>(), 0.5);
  EXPECT_DOUBLE_EQ(radius * p["left_wheel_radius_multiplier"].as<double>(), 0.0981);
  EXPECT_DOUBLE_EQ(radius * p["right_wheel_radius_multiplier"].as<double>(), 0.1013);
  EXPECT_DOUBLE_EQ(0.5 * p["wheel_separation_multiplier"].as<double>(), 0.5234);
  const YAML::Node tf = root["base_link_to_laser"]["ros__parameters"];
  EXPECT_EQ(tf["frame_id"].as<std::string>(), "base_link");
  EXPECT_EQ(tf["child_frame_id"].as<std::string>(), "laser");
  EXPECT_EQ(tf["x"].as<double>(), 0.12);
  EXPECT_EQ(tf["y"].as<double>(), -0.04);
  EXPECT_EQ(tf["yaw"].as<double>(), SE2(0.12, -0.04, 0.3).yaw);
  const auto args = tf["arguments"].as<std::vector<std::string>>();
  ASSERT_EQ(args.size(), 16u);
  EXPECT_EQ(args[0], "--x");
  EXPECT_EQ(std::stod(args[1]), 0.12);
  EXPECT_EQ(args[14], "--child-frame-id");
  EXPECT_EQ(args[15], "laser");
}

}  // namespace
}  // namespace slamprep::eval
