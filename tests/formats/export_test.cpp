// Export: every MCAP message decoded by the independent @mcap/core reader (node) and checked
// against the dataset; CARMEN field order; TUM/KITTI trajectories; CSM laser_data.
#include "eval/formats/export.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/odometry.hpp"
#include "eval/formats/ros2_messages.hpp"
#include "eval/formats/text_io.hpp"
#include "eval/formats/tum.hpp"
#include "node_tool.hpp"
#include "synthetic_dataset.hpp"

namespace slamprep::eval {
namespace {
namespace fs = std::filesystem;

fs::path scratch(const std::string& name) {
  const fs::path dir =
      fs::temp_directory_path() / ("slamprep_formats_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir / name;
}

ExportInput syntheticInput() {
  ExportInput in;
  in.dataset = test::makeSyntheticDataset();
  in.deskewed["linear"] = in.dataset.scans;  // stands in for a de-skew output
  in.calibration = CalibrationChoice{*in.dataset.info.true_geometry, "joint"};
  return in;
}

struct Decoded {
  nlohmann::json summary;
  std::map<std::string, std::vector<nlohmann::json>> topics;
};

Decoded decodeWithNode(const fs::path& bag) {
  const fs::path out = bag.string() + ".jsonl";
  std::string log;
  EXPECT_EQ(test::runNodeTool("read '" + bag.string() + "' '" + out.string() + "'", &log), 0)
      << log;
  Decoded d;
  std::ifstream in(out);
  std::string line;
  std::getline(in, line);
  d.summary = nlohmann::json::parse(line);
  while (std::getline(in, line)) {
    nlohmann::json j = nlohmann::json::parse(line);
    d.topics[j["topic"].get<std::string>()].push_back(std::move(j));
  }
  return d;
}

std::uint64_t ns(const nlohmann::json& stamp) {
  return std::uint64_t(stamp["sec"].get<std::int64_t>()) * 1000000000u +
         stamp["nanosec"].get<std::uint64_t>();
}

double number(const nlohmann::json& j) {
  if (j.is_string()) return j == "Infinity" ? INFINITY : j == "-Infinity" ? -INFINITY : NAN;
  return j.get<double>();
}

void checkBag(const ExportInput& in, const fs::path& bag, bool chunked) {
  const Dataset& d = in.dataset;
  const Decoded dec = decodeWithNode(bag);
  const std::size_t total = 2 * d.scans.size() + d.odom_nominal.size() + d.encoders.size() +
                            d.imu.size() + d.encoders.size() + d.groundtruth.size() + 1;
  const auto& s = dec.summary;
  EXPECT_EQ(s["profile"], "ros2");
  EXPECT_EQ(s["stream_messages"].get<std::size_t>(), total);
  EXPECT_EQ(s["indexed_messages"].get<std::size_t>(), chunked ? total : 0u);
  EXPECT_EQ(s["statistics"]["messageCount"], std::to_string(total));
  for (const auto& c : s["channels"]) {
    const std::string topic = c["topic"];
    const auto decoded = dec.topics.count(topic) ? dec.topics.at(topic).size() : 0u;
    EXPECT_EQ(s["statistics"]["channelMessageCounts"][std::to_string(c["id"].get<int>())],
              std::to_string(decoded))
        << topic;
  }
  EXPECT_EQ(s["trailing_bytes_messages"], 0) << "a message's CDR length disagrees with its schema";
  EXPECT_EQ(s["unordered_log_times"], 0);
  EXPECT_EQ(s["summary_offsets"].get<int>(), chunked ? 4 : 3);  // schema, channel, stats, chunks
  EXPECT_EQ(s["channels"].size(), 8u);
  for (const auto& c : s["channels"])
    EXPECT_NE(c["metadata"]["offered_qos_profiles"].get<std::string>().find(
                  c["topic"] == "/tf_static" ? "durability: 1" : "durability: 2"),
              std::string::npos);

  ASSERT_EQ(dec.topics.at("/scan").size(), d.scans.size());
  EXPECT_EQ(dec.topics.at("/scan_deskewed/linear").size(), d.scans.size());
  ASSERT_EQ(dec.topics.at("/odom").size(), d.odom_nominal.size());
  EXPECT_EQ(dec.topics.at("/odom_calibrated").size(), d.encoders.size());
  EXPECT_EQ(dec.topics.at("/imu").size(), d.imu.size());
  ASSERT_EQ(dec.topics.at("/joint_states").size(), d.encoders.size());
  EXPECT_EQ(dec.topics.at("/tf").size(), d.groundtruth.size());
  ASSERT_EQ(dec.topics.at("/tf_static").size(), 1u);

  for (std::size_t k = 0; k < d.scans.size(); ++k) {
    const LaserScan& scan = d.scans[k].scan;
    const auto& rec = dec.topics.at("/scan")[k];
    const auto& m = rec["msg"];
    const std::size_t n = scan.size();
    EXPECT_EQ(ns(m["header"]["stamp"]),
              std::uint64_t(rosTimeFromSeconds(scan.stamp_s, "").nanoseconds()));
    EXPECT_EQ(m["header"]["frame_id"], "laser");
    EXPECT_EQ(number(m["angle_min"]), double(float(scan.angle_min_rad)));
    EXPECT_EQ(number(m["angle_increment"]), double(float(scan.angle_increment_rad)));
    EXPECT_EQ(number(m["angle_max"]), double(float(scan.beamAngle(n - 1))));
    EXPECT_EQ(number(m["time_increment"]), double(float(scan.time_increment_s)));
    EXPECT_EQ(number(m["scan_time"]), double(float(scan.scan_time_s)));
    EXPECT_EQ(number(m["range_min"]), double(float(scan.range_min_m)));
    EXPECT_EQ(number(m["range_max"]), double(float(scan.range_max_m)));
    ASSERT_EQ(m["ranges"].size(), n);
    for (std::size_t i = 0; i < n; ++i)
      ASSERT_EQ(number(m["ranges"][i]), double(float(scan.ranges_m[i]))) << k << " " << i;
    // The bag is consistent with its own fields: logged when the last beam is in,
    // log_time = stamp + (n-1) time_increment. The float32 time_increment is off by at most
    // 2^-24 relative, times (n-1) beams, plus 1 ns of stamp rounding.
    const double ti = number(m["time_increment"]);
    const double predicted_ns = double(ns(m["header"]["stamp"])) + (n - 1) * ti * 1e9;
    const double tol_ns = 1.0 + (n - 1) * ti * 1e9 * std::ldexp(1.0, -24);
    EXPECT_NEAR(std::stod(rec["log_time"].get<std::string>()), predicted_ns, tol_ns);
    EXPECT_EQ(rec["log_time"], rec["publish_time"]);
  }
  for (std::size_t k = 0; k < d.odom_nominal.size(); ++k) {
    const auto& m = dec.topics.at("/odom")[k]["msg"];
    const SE2& T = d.odom_nominal[k].value;
    EXPECT_EQ(m["header"]["frame_id"], "odom");
    EXPECT_EQ(m["child_frame_id"], "base_link");
    EXPECT_EQ(m["pose"]["pose"]["position"]["x"].get<double>(), T.x);
    EXPECT_EQ(m["pose"]["pose"]["position"]["y"].get<double>(), T.y);
    EXPECT_EQ(m["pose"]["pose"]["orientation"]["z"].get<double>(), std::sin(T.yaw / 2));
    EXPECT_EQ(ns(m["header"]["stamp"]),
              std::uint64_t(rosTimeFromSeconds(d.odom_nominal[k].stamp_s, "").nanoseconds()));
  }
  // The arc: the odometry twist is the nominal-geometry (v, w) of the true wheel rates. One step
  // is off by up to 1 tick per wheel (3 %), but ticks are cumulative, so the mean over the 100
  // steps 50..149 (1 s) is off by at most 1 tick per wheel over 1 s: 1.53e-3 rad -> v within
  // r * 1.53e-3 = 1.5e-4 m/s, w within 2 r * 1.53e-3 / b = 6.1e-4 rad/s.
  double v_mean = 0, w_mean = 0;
  for (int k = 50; k < 150; ++k) {
    const auto& tw = dec.topics.at("/odom")[k]["msg"]["twist"]["twist"];
    v_mean += tw["linear"]["x"].get<double>() / 100;
    w_mean += tw["angular"]["z"].get<double>() / 100;
  }
  const Eigen::Vector2d rates = d.info.true_geometry->wheelRates(0.5, 0.3);
  const Eigen::Vector2d vw = d.info.nominal_geometry.twist(rates.x(), rates.y());
  EXPECT_NEAR(v_mean, vw.x(), 2e-4);
  EXPECT_NEAR(w_mean, vw.y(), 7e-4);

  const double rad_per_tick = radiansPerTick(d.info.ticks_per_revolution);
  for (std::size_t k = 0; k < d.encoders.size(); ++k) {
    const auto& m = dec.topics.at("/joint_states")[k]["msg"];
    EXPECT_EQ(m["name"][0], "wheel_left_joint");
    EXPECT_EQ(m["position"][0].get<double>(), double(d.encoders[k].ticks_left) * rad_per_tick);
    EXPECT_EQ(m["position"][1].get<double>(), double(d.encoders[k].ticks_right) * rad_per_tick);
  }
  const auto& tf = dec.topics.at("/tf")[7]["msg"]["transforms"][0];
  EXPECT_EQ(tf["header"]["frame_id"], "world");
  EXPECT_EQ(tf["child_frame_id"], "base_link");
  EXPECT_EQ(tf["transform"]["translation"]["x"].get<double>(), d.groundtruth[7].value.x);
  const auto& st = dec.topics.at("/tf_static")[0];
  EXPECT_EQ(st["log_time"], "0");
  const auto& mount = st["msg"]["transforms"][0];
  EXPECT_EQ(mount["header"]["frame_id"], "base_link");
  EXPECT_EQ(mount["child_frame_id"], "laser");
  EXPECT_EQ(mount["transform"]["translation"]["x"].get<double>(), d.info.T_base_lidar.x);
  EXPECT_EQ(mount["transform"]["rotation"]["z"].get<double>(),
            std::sin(d.info.T_base_lidar.yaw / 2));
  const auto& imu = dec.topics.at("/imu")[3]["msg"];
  EXPECT_EQ(imu["angular_velocity"]["z"].get<double>(), d.imu[3].gyro_z_radps);
  EXPECT_EQ(imu["orientation_covariance"][0].get<double>(), -1.0);
}

TEST(ExportMcap, IndependentReaderDecodesEveryMessageChunked) {
  if (const std::string why = test::nodeToolUnavailable(); !why.empty()) GTEST_SKIP() << why;
  const ExportInput in = syntheticInput();
  ExportParams p;
  p.mcap_chunk_size_bytes = 64 * 1024;  // several chunks
  const fs::path bag = scratch("chunked.mcap");
  const ExportResult r = exportDataset(in, ExportFormat::kMcap, bag, p);
  EXPECT_EQ(r.counts.at("/scan"), in.dataset.scans.size());
  checkBag(in, bag, true);
}

TEST(ExportMcap, IndependentReaderDecodesEveryMessageUnchunked) {
  if (const std::string why = test::nodeToolUnavailable(); !why.empty()) GTEST_SKIP() << why;
  const ExportInput in = syntheticInput();
  ExportParams p;
  p.mcap_chunk_size_bytes = 0;
  const fs::path bag = scratch("plain.mcap");
  exportDataset(in, ExportFormat::kMcap, bag, p);
  checkBag(in, bag, false);
}

TEST(ExportMcap, IsDeterministicAndLeavesNoPartialFile) {
  const ExportInput in = syntheticInput();
  const std::string a = formatMcap(in, {});
  EXPECT_EQ(a, formatMcap(in, {}));
  const fs::path bag = scratch("det.mcap");
  exportDataset(in, ExportFormat::kMcap, bag);
  EXPECT_EQ(readFile(bag), a);
  for (const auto& e : fs::directory_iterator(bag.parent_path()))
    EXPECT_EQ(e.path().filename().string().find(".partial-"), std::string::npos);
}

TEST(ExportMcap, RefusesNegativeStampsNamingTheFile) {
  ExportInput in = syntheticInput();
  test::SyntheticParams sp;
  sp.start_s = -5.0;
  in.dataset = test::makeSyntheticDataset(sp);
  in.deskewed.clear();
  try {
    formatMcap(in, {});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("negative stamp"), std::string::npos) << e.what();
  }
}

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
  const fs::path dir = scratch("tum");
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
  const fs::path dir = scratch("kitti");
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

TEST(ExportFormat, UnknownFormatsAreInputErrors) {
  EXPECT_EQ(parseExportFormat("kitti"), ExportFormat::kKitti);
  EXPECT_THROW(parseExportFormat("bag"), InputError);
}

}  // namespace
}  // namespace slamprep::eval
