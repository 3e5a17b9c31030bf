// MCAP export: every message decoded by the independent @mcap/core reader (node) and checked
// against the dataset; determinism and refusals.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "export_input.hpp"
#include "node_tool.hpp"
#include "slamprep/core/atomic_file.hpp"
#include "slamprep/core/error.hpp"
#include "slamprep/core/odometry.hpp"
#include "slamprep/eval/formats/export.hpp"
#include "slamprep/eval/formats/ros2_messages.hpp"
#include "slamprep/tests/support/scratch_dir.hpp"
#include "synthetic_dataset.hpp"

namespace slamprep::eval {
namespace {
namespace fs = std::filesystem;
using test::ScratchDir;
using test::syntheticInput;

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

// `compression`: of the chunks ("" = uncompressed); empty `chunked` files have none.
void checkBag(const ExportInput& in, const fs::path& bag, bool chunked,
              const std::string& compression) {
  const Dataset& d = in.dataset;
  const Decoded dec = decodeWithNode(bag);
  // Scans and de-skewed scans, /odom and /tf from the nominal odometry, /odom_calibrated and
  // /joint_states from the encoders, /imu, /ground_truth, one /tf_static.
  const std::size_t total = 2 * d.scans.size() + 2 * d.odom_nominal.size() + 2 * d.encoders.size() +
                            d.imu.size() + d.groundtruth.size() + 1;
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
  // Schema, channel, statistics, metadata index and (chunked) chunk index groups.
  EXPECT_EQ(s["summary_offsets"].get<int>(), chunked ? 5 : 4);
  EXPECT_EQ(s["chunk_compressions"],
            chunked ? nlohmann::json::array({compression}) : nlohmann::json::array());
  EXPECT_EQ(s["channels"].size(), 9u);
  // The nominal geometry travels in slamprep's Metadata record, indexed in the summary.
  ASSERT_EQ(s["metadata"].size(), 1u);
  EXPECT_EQ(s["metadata"][0]["name"], "slamprep");
  EXPECT_EQ(std::stod(s["metadata"][0]["entries"]["nominal_wheel_base_m"].get<std::string>()),
            d.info.nominal_geometry.wheel_base_m);
  EXPECT_EQ(s["metadata_indexes"], nlohmann::json::array({"slamprep"}));
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
  ASSERT_EQ(dec.topics.at("/tf").size(), d.odom_nominal.size());
  ASSERT_EQ(dec.topics.at("/ground_truth").size(), d.groundtruth.size());
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
  // REP 105: /tf holds odom -> base_link (the wheel odometry), and only that; the ground truth
  // has its own topic, never world -> base_link in the tree.
  for (std::size_t k = 0; k < d.odom_nominal.size(); ++k) {
    const auto& tf = dec.topics.at("/tf")[k]["msg"]["transforms"];
    ASSERT_EQ(tf.size(), 1u);
    ASSERT_EQ(tf[0]["header"]["frame_id"], "odom");
    ASSERT_EQ(tf[0]["child_frame_id"], "base_link");
    ASSERT_EQ(tf[0]["transform"]["translation"]["x"].get<double>(), d.odom_nominal[k].value.x);
    ASSERT_EQ(tf[0]["transform"]["rotation"]["z"].get<double>(),
              std::sin(d.odom_nominal[k].value.yaw / 2));
  }
  for (std::size_t k = 0; k < d.groundtruth.size(); ++k) {
    const auto& m = dec.topics.at("/ground_truth")[k]["msg"];
    ASSERT_EQ(m["header"]["frame_id"], "world");
    ASSERT_EQ(m["child_frame_id"], "base_link");
    ASSERT_EQ(m["pose"]["pose"]["position"]["x"].get<double>(), d.groundtruth[k].value.x);
    ASSERT_EQ(m["pose"]["pose"]["position"]["y"].get<double>(), d.groundtruth[k].value.y);
  }
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

TEST(ExportMcap, IndependentReaderDecodesEveryMessageChunkedWithZstd) {
  SLAMPREP_REQUIRE_NODE_TOOL();
  const ExportInput in = syntheticInput();
  ExportParams p;                       // zstd by default
  p.mcap_chunk_size_bytes = 64 * 1024;  // several chunks
  const ScratchDir scratch("export_mcap");
  const fs::path bag = scratch / "chunked.mcap";
  const ExportResult r = exportDataset(in, ExportFormat::kMcap, bag, p);
  EXPECT_EQ(r.counts.at("/scan"), in.dataset.scans.size());
  checkBag(in, bag, true, "zstd");
}

TEST(ExportMcap, IndependentReaderDecodesLz4AndUncompressedChunks) {
  SLAMPREP_REQUIRE_NODE_TOOL();
  const ExportInput in = syntheticInput();
  const ScratchDir scratch("export_mcap");
  for (const Compression c : {Compression::kLz4, Compression::kNone}) {
    ExportParams p;
    p.mcap_chunk_size_bytes = 64 * 1024;
    p.mcap_compression = c;
    const fs::path bag = scratch / ("chunked_" + std::string(mcapCompressionName(c)) + ".mcap");
    exportDataset(in, ExportFormat::kMcap, bag, p);
    checkBag(in, bag, true, std::string(mcapCompressionName(c)));
  }
}

TEST(ExportMcap, IndependentReaderDecodesEveryMessageUnchunked) {
  SLAMPREP_REQUIRE_NODE_TOOL();
  const ExportInput in = syntheticInput();
  ExportParams p;
  p.mcap_chunk_size_bytes = 0;
  const ScratchDir scratch("export_mcap");
  const fs::path bag = scratch / "plain.mcap";
  exportDataset(in, ExportFormat::kMcap, bag, p);
  checkBag(in, bag, false, "");
}

TEST(ExportMcap, IsDeterministicAndLeavesNoPartialFile) {
  const ExportInput in = syntheticInput();
  const std::string a = formatMcap(in, {});
  EXPECT_EQ(a, formatMcap(in, {}));
  const ScratchDir scratch("export_mcap");
  const fs::path bag = scratch / "det.mcap";
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

}  // namespace
}  // namespace slamprep::eval
