// Export to text formats: CARMEN field order, TUM/KITTI trajectories, CSM laser_data, the
// calibration choice and format names.
#include "slamprep/eval/formats/export.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>

#include "export_input.hpp"
#include "slamprep/core/atomic_file.hpp"
#include "slamprep/core/error.hpp"
#include "slamprep/eval/formats/scan_jsonl.hpp"
#include "slamprep/eval/formats/text_io.hpp"
#include "slamprep/eval/formats/tum.hpp"
#include "slamprep/tests/support/scratch_dir.hpp"
#include "synthetic_dataset.hpp"

namespace slamprep::eval {
namespace {
namespace fs = std::filesystem;
using test::ScratchDir;
using test::syntheticInput;

std::vector<std::string> tokens(const std::string& line) {
  std::vector<std::string_view> f;
  slamprep::eval::splitWhitespace(line, f);
  return {f.begin(), f.end()};
}

TEST(ExportCarmen, FieldsSitWhereTheCarmenFormatPutsThem) {
  const Dataset d = test::makeSyntheticDataset();
  const std::string text = formatCarmen(d, d.scans, {});
  std::istringstream in(text);
  std::string line;
  std::vector<std::vector<std::string>> lasers, odoms;
  std::map<std::string, double> params;
  double last = -1;
  while (std::getline(in, line)) {
    if (line[0] == '#') continue;
    auto t = tokens(line);
    if (t[0] == "PARAM") {
      params[t[1]] = std::stod(t[2]);
      continue;
    }
    const double stamp = std::stod(t[t.size() - 3]);  // timestamp hostname logger_timestamp
    EXPECT_GE(stamp, last) << "lines must be in time order";
    last = stamp;
    EXPECT_EQ(t[t.size() - 2], "slamprep");
    (t[0] == "ODOM" ? odoms : lasers).push_back(t);
  }
  ASSERT_EQ(odoms.size(), d.odom_nominal.size());
  ASSERT_EQ(lasers.size(), d.scans.size());
  EXPECT_EQ(params["robot_frontlaser_offset"], d.info.T_base_lidar.x);
  EXPECT_EQ(params["robot_frontlaser_side_offset"], d.info.T_base_lidar.y);
  EXPECT_EQ(params["robot_frontlaser_angular_offset"], d.info.T_base_lidar.yaw);
  EXPECT_EQ(params["slamprep_nominal_b"], d.info.nominal_geometry.wheel_base_m);
  EXPECT_EQ(params["slamprep_time_increment"], d.scans[0].scan.time_increment_s);
  // ODOM x y theta tv rv accel timestamp hostname logger_timestamp
  ASSERT_EQ(odoms[50].size(), 10u);
  EXPECT_EQ(std::stod(odoms[50][1]), d.odom_nominal[50].value.x);
  EXPECT_EQ(std::stod(odoms[50][3]), d.odom_nominal[50].value.yaw);
  // ROBOTLASER1 laser_type start_angle fov res max_range accuracy remission_mode n [n ranges]
  // num_remissions laser_pose(3) robot_pose(3) tv rv forward side turn_axis timestamp host ts
  const auto& l = lasers[4];
  const LaserScan& s = d.scans[4].scan;
  const std::size_t n = s.size();
  ASSERT_EQ(l.size(), 9 + n + 1 + 6 + 5 + 3);
  EXPECT_EQ(std::stod(l[2]), s.angle_min_rad);
  EXPECT_NEAR(std::stod(l[3]), (n - 1) * s.angle_increment_rad, 1e-12);
  EXPECT_EQ(std::stod(l[4]), s.angle_increment_rad);
  EXPECT_EQ(std::stod(l[5]), s.range_max_m);
  EXPECT_EQ(std::stoul(l[8]), n);
  EXPECT_EQ(std::stod(l[9]), s.ranges_m[0]);
  EXPECT_EQ(std::stod(l[9 + 5]), s.range_max_m) << "no return is written as the max range";
  EXPECT_EQ(l[9 + n], "0");
  const SE2 robot = *d.odom_nominal.at(s.stamp_s);
  const SE2 laser = robot * d.info.T_base_lidar;
  EXPECT_EQ(std::stod(l[10 + n]), laser.x);
  EXPECT_EQ(std::stod(l[12 + n]), laser.yaw);
  EXPECT_EQ(std::stod(l[13 + n]), robot.x);
  EXPECT_EQ(std::stod(l[15 + n]), robot.yaw);
  EXPECT_EQ(std::stod(l[21 + n]), s.stamp_s);
}

TEST(ExportCarmen, ClockwiseScansAreWrittenLastBeamFirst) {
  test::SyntheticParams sp;
  sp.clockwise = true;
  const Dataset d = test::makeSyntheticDataset(sp);
  std::istringstream in(formatCarmen(d, d.scans, {}));
  std::string line;
  while (std::getline(in, line) && line.rfind("ROBOTLASER1", 0) != 0) {
  }
  const auto t = tokens(line);
  const LaserScan& s = d.scans[0].scan;
  EXPECT_EQ(std::stod(t[2]), s.beamAngle(s.size() - 1));
  EXPECT_GT(std::stod(t[4]), 0.0);
  EXPECT_EQ(std::stod(t[9]), s.ranges_m.back());
}

TEST(ExportTum, TrajectoriesReadBackAndOdometryStartsOnTheTruth) {
  const ExportInput in = syntheticInput();
  const ScratchDir scratch("export_tum");
  const fs::path dir = scratch / "tum";
  exportDataset(in, ExportFormat::kTum, dir);
  const PoseSeries gt = slamprep::eval::readTum(dir / "groundtruth.tum");
  const PoseSeries nominal = slamprep::eval::readTum(dir / "odom_nominal.tum");
  const PoseSeries calibrated = slamprep::eval::readTum(dir / "odom_calibrated.tum");
  ASSERT_EQ(gt.size(), in.dataset.groundtruth.size());
  ASSERT_EQ(nominal.size(), in.dataset.odom_nominal.size());
  // Anchored: both odometries start on the true start pose (to rounding of one composition).
  EXPECT_NEAR(nominal[0].value.x, gt[0].value.x, 1e-12);
  EXPECT_NEAR(calibrated[0].value.yaw, gt[0].value.yaw, 1e-12);
  // The calibrated (= true) geometry tracks the truth to tick rounding: 1.5e-3 rad per tick on
  // a 0.1 m wheel = 0.15 mm per sample, not accumulating (cumulative ticks): well under 1 mm.
  // The nominal one drifts by centimetres.
  const SE2 g_end = *gt.at(calibrated.backStamp());
  EXPECT_LT((calibrated[calibrated.size() - 1].value.translation() - g_end.translation()).norm(),
            1e-3);
  EXPECT_GT((nominal[nominal.size() - 1].value.translation() - g_end.translation()).norm(), 1e-2);
}

TEST(ExportKitti, OneRowMajor3x4PosePerScanStartingAtIdentity) {
  const ExportInput in = syntheticInput();
  const ScratchDir scratch("export_kitti");
  const fs::path dir = scratch / "kitti";
  exportDataset(in, ExportFormat::kKitti, dir);
  for (const char* name : {"groundtruth.txt", "odom_nominal.txt", "odom_calibrated.txt"}) {
    std::ifstream f(dir / name);
    std::string line;
    std::vector<std::string> lines;
    while (std::getline(f, line)) lines.push_back(line);
    ASSERT_EQ(lines.size(), in.dataset.scans.size()) << name;
    EXPECT_EQ(lines[0], "1 0 0 0 0 1 0 0 0 0 1 0") << name;
    EXPECT_EQ(tokens(lines[5]).size(), 12u);
  }
  std::ifstream times(dir / "times.txt");
  double t0;
  times >> t0;
  EXPECT_EQ(t0, in.dataset.scans[0].scan.stamp_s);
  // Row 7 of the ground truth is T_0^-1 T_7 (x = r03, y = r13).
  std::ifstream gt(dir / "groundtruth.txt");
  std::string line;
  for (int i = 0; i <= 7; ++i) std::getline(gt, line);
  const auto t = tokens(line);
  const SE2 rel = between(*in.dataset.groundtruth.at(in.dataset.scans[0].scan.stamp_s),
                          *in.dataset.groundtruth.at(in.dataset.scans[7].scan.stamp_s));
  EXPECT_NEAR(std::stod(t[3]), rel.x, 1e-12);
  EXPECT_NEAR(std::stod(t[7]), rel.y, 1e-12);
}

TEST(ExportCsm, CsmKeysOnlyAndClockwiseScansReversed) {
  test::SyntheticParams sp;
  sp.clockwise = true;
  const Dataset d = test::makeSyntheticDataset(sp);
  std::istringstream in(formatCsm(d.scans));
  std::string line;
  std::getline(in, line);
  const nlohmann::json j = nlohmann::json::parse(line);
  const LaserScan& s = d.scans[0].scan;
  EXPECT_FALSE(j.contains("stamp_s"));
  EXPECT_LT(j["min_theta"].get<double>(), j["max_theta"].get<double>());
  for (std::size_t i = 1; i < s.size(); ++i)
    ASSERT_GT(j["theta"][i].get<double>(), j["theta"][i - 1].get<double>());
  EXPECT_EQ(j["readings"][0].get<double>(), s.ranges_m.back());
  EXPECT_TRUE(j["readings"][s.size() - 1 - 5].is_null());  // beam 5 has no return
  EXPECT_EQ(j["valid"][s.size() - 1 - 5], 0);
  EXPECT_EQ(j["odometry"][0].get<double>(), d.scans[0].T_odom_base_nominal->x);
}

// A de-skewed scan (p_ref off the grid: every point 0.2-0.4 of a beam past its beam angle, as
// a robot that turns and accelerates leaves them) is exported ray by ray at the exact angles, and
// the project's CSM reader (parseScanLine) gives the same points back: 1e-12 m covers |p| and atan2
// written as shortest round-trip decimals and cos/sin on reading (a few roundings at 3 m).
TEST(ExportCsm, DeskewedScansCarryTheExactThetaAndRoundTrip) {
  for (double sign : {1.0, -1.0}) {
    ScanRecord record;
    LaserScan& s = record.scan;
    s.stamp_s = 12.5;
    s.angle_increment_rad = sign * 2.0 * std::numbers::pi / 360.0;
    s.angle_min_rad = -sign * std::numbers::pi;
    s.range_min_m = 0.1;
    s.range_max_m = 20.0;
    s.ranges_m.assign(360, 2.0);  // the repacked grid: not what this test is about
    for (std::size_t i = 0; i < 360; ++i) {
      const double angle =
          s.beamAngle(i) + (0.3 + 0.1 * std::sin(0.05 * i)) * s.angle_increment_rad;
      const double r = 2.0 + 0.5 * std::sin(0.1 * i);
      const Eigen::Vector2d p = r * Eigen::Vector2d(std::cos(angle), std::sin(angle));
      record.p_ref.push_back(i % 50 == 7 ? std::nullopt : std::optional(p));
    }
    const std::string line = formatCsm({record});
    const nlohmann::json j = nlohmann::json::parse(line);
    ASSERT_EQ(j["nrays"], 360u);
    EXPECT_EQ(j["min_theta"], j["theta"][0]);  // CSM's ld_valid_fields checks both ends
    EXPECT_EQ(j["max_theta"], j["theta"][359]);
    EXPECT_LE(j["max_theta"].get<double>() - j["min_theta"].get<double>(), 2 * std::numbers::pi);
    for (std::size_t k = 0; k < 360; ++k) {
      const std::size_t i = sign > 0 ? k : 359 - k;  // clockwise: reversed
      if (k) {
        ASSERT_GT(j["theta"][k].get<double>(), j["theta"][k - 1].get<double>()) << k;
      }
      if (!record.p_ref[i]) {  // its angle: the offset of the ray before it (monotone above)
        EXPECT_TRUE(j["readings"][k].is_null());
        EXPECT_EQ(j["valid"][k], 0);
        continue;
      }
      const double expected =
          s.beamAngle(i) + (0.3 + 0.1 * std::sin(0.05 * i)) * s.angle_increment_rad;
      EXPECT_NEAR(j["theta"][k].get<double>(), expected, 1e-12) << k;
      EXPECT_NEAR(j["readings"][k].get<double>(), record.p_ref[i]->norm(), 1e-15) << k;
    }
    const ScanRecord back = parseScanLine(line, TextLocation{"csm", 1});
    ASSERT_EQ(back.p_ref.size(), 360u);
    for (std::size_t k = 0; k < 360; ++k) {
      const auto& original = record.p_ref[sign > 0 ? k : 359 - k];
      ASSERT_EQ(back.p_ref[k].has_value(), original.has_value()) << k;
      if (original) {
        EXPECT_LT((*back.p_ref[k] - *original).norm(), 1e-12) << k;
      }
    }
  }
}

// Points that turn past 2 pi (the robot turned with the lidar) are cut where they overlap the
// start: CSM refuses a field of view over 2 pi. An on-grid scan reads back without p_ref.
TEST(ExportCsm, ExactRaysAreCutToOneTurn) {
  ScanRecord record;
  LaserScan& s = record.scan;
  s.angle_increment_rad = 2.0 * std::numbers::pi / 360.0;
  s.angle_min_rad = 0.0;
  s.range_max_m = 20.0;
  s.ranges_m.assign(360, 2.0);
  for (std::size_t i = 0; i < 360; ++i) {
    const double angle = s.beamAngle(i) * (1.0 + 0.1 / (2.0 * std::numbers::pi));  // 0.1 rad more
    record.p_ref.push_back(2.0 * Eigen::Vector2d(std::cos(angle), std::sin(angle)));
  }
  const nlohmann::json j = nlohmann::json::parse(formatCsm({record}));
  const std::size_t n = j["nrays"].get<std::size_t>();
  EXPECT_LT(n, 360u);
  EXPECT_GT(n, 350u);  // 0.1 rad is 5.7 beams
  EXPECT_LE(j["max_theta"].get<double>() - j["min_theta"].get<double>(), 2 * std::numbers::pi);
  record.p_ref.clear();
  EXPECT_TRUE(parseScanLine(formatCsm({record}), TextLocation{"csm", 1}).p_ref.empty());
}

// The de-skewed points travel through deskewed_<method>.jsonl as "p_ref".
TEST(ExportCsm, ScanLinesCarryPref) {
  ScanRecord record;
  record.scan.angle_increment_rad = 0.1;
  record.scan.range_max_m = 20.0;
  record.scan.ranges_m = {1.0, 2.0, 3.0};
  record.p_ref = {Eigen::Vector2d(1.0, 0.25), std::nullopt, Eigen::Vector2d(-0.1, 3.0)};
  std::string line;
  appendScanLine(line, record, TextLocation{"deskewed_imu.jsonl", 1});
  const ScanRecord back = parseScanLine(line, TextLocation{"deskewed_imu.jsonl", 1});
  ASSERT_EQ(back.p_ref.size(), 3u);
  EXPECT_EQ(*back.p_ref[0], *record.p_ref[0]);
  EXPECT_FALSE(back.p_ref[1]);
  EXPECT_EQ(*back.p_ref[2], *record.p_ref[2]);
}

TEST(ExportCsm, Sm2CommandLineCarriesTheMount) {
  EXPECT_NE(sm2CommandLine("out.csm", SE2(0.1, -0.02, 0.5))
                .find("sm2 -in out.csm -laser_x 0.1 -laser_y -0.02 -laser_theta 0.5"),
            std::string::npos);
}

TEST(ExportFormat, UnknownFormatsAreInputErrors) {
  EXPECT_EQ(parseExportFormat("kitti"), ExportFormat::kKitti);
  EXPECT_THROW(parseExportFormat("bag"), InputError);
}

}  // namespace
}  // namespace slamprep::eval
