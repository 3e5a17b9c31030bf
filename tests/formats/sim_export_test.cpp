// A dataset from the real simulator (Bullet physics, 3 s of worlds/scenarios/arc.yaml in the
// room) exported to MCAP and decoded message by message by the independent @mcap/core reader;
// also imported back and checked against the original. Label `sim`.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "node_tool.hpp"
#include "slamprep/core/error.hpp"
#include "slamprep/core/odometry.hpp"
#include "slamprep/eval/formats/export.hpp"
#include "slamprep/eval/formats/import.hpp"
#include "slamprep/eval/formats/ros2_messages.hpp"
#include "slamprep/sim/drive/simulator.hpp"
#include "slamprep/tests/support/scratch_dir.hpp"

namespace slamprep::eval {
namespace {
namespace fs = std::filesystem;

const Dataset& simulated() {
  static const Dataset d = [] {
    sim::SimConfig c;
    c.scenario = "worlds/scenarios/arc.yaml";
    c.duration_s = 3.0;
    c.seed = 11;
    return sim::simulate(c).dataset;
  }();
  return d;
}

TEST(SimExport, IndependentReaderDecodesEveryMessageOfASimulatedRun) {
  SLAMPREP_REQUIRE_NODE_TOOL();
  const Dataset& d = simulated();
  ASSERT_GT(d.scans.size(), 20u);
  ExportInput in;
  in.dataset = d;
  const test::ScratchDir scratch("sim_export");
  const fs::path bag = scratch / "sim.mcap", out = scratch / "sim.jsonl";
  const ExportResult r = exportDataset(in, ExportFormat::kMcap, bag);
  std::string log;
  ASSERT_EQ(test::runNodeTool("read '" + bag.string() + "' '" + out.string() + "'", &log), 0)
      << log;
  std::ifstream f(out);
  std::string line;
  std::getline(f, line);
  const nlohmann::json summary = nlohmann::json::parse(line);
  std::size_t total = 0;
  for (const auto& [topic, n] : r.counts) total += n;
  // /odom and /tf (odom -> base_link) from the nominal odometry, /ground_truth, one /tf_static.
  EXPECT_EQ(total, d.scans.size() + 2 * d.odom_nominal.size() + d.imu.size() + d.encoders.size() +
                       d.groundtruth.size() + 1);
  EXPECT_EQ(summary["chunk_compressions"], nlohmann::json::array({"zstd"}));
  EXPECT_EQ(summary["stream_messages"].get<std::size_t>(), total);
  EXPECT_EQ(summary["indexed_messages"].get<std::size_t>(), total);
  EXPECT_EQ(summary["trailing_bytes_messages"], 0);
  std::size_t k = 0;
  while (std::getline(f, line)) {
    const nlohmann::json j = nlohmann::json::parse(line);
    if (j["topic"] != "/scan") continue;
    const LaserScan& s = d.scans[k++].scan;
    const auto& m = j["msg"];
    const auto& stamp = m["header"]["stamp"];
    EXPECT_EQ(stamp["sec"].get<std::int64_t>() * 1000000000 + stamp["nanosec"].get<std::int64_t>(),
              rosTimeFromSeconds(s.stamp_s, "").nanoseconds());
    ASSERT_EQ(m["ranges"].size(), s.size());
    EXPECT_EQ(m["time_increment"].get<double>(), double(float(s.time_increment_s)));
    EXPECT_GT(s.time_increment_s, 0.0);
    // log time = last beam: stamp + (n-1) time_increment, to 1 ns of rounding.
    const double last_ns = std::round(s.endTime() * 1e9);
    EXPECT_NEAR(std::stod(j["log_time"].get<std::string>()), last_ns, 1.0);
    for (std::size_t i = 0; i < s.size(); i += 37) {
      if (std::isfinite(s.ranges_m[i]))
        EXPECT_EQ(m["ranges"][i].get<double>(), double(float(s.ranges_m[i])));
      else
        EXPECT_EQ(m["ranges"][i], "Infinity");
    }
  }
  EXPECT_EQ(k, d.scans.size());
}

TEST(SimExport, ImportedBagKeepsEncodersExactlyAndScansToFloat) {
  const Dataset& d = simulated();
  ExportInput in;
  in.dataset = d;
  ImportParams p;
  p.nominal_geometry = d.info.nominal_geometry;
  p.ticks_per_revolution = d.info.ticks_per_revolution;
  const ImportResult r = importMcap(formatMcap(in, {}), "sim.mcap", p);
  ASSERT_EQ(r.dataset.encoders.size(), d.encoders.size());
  for (std::size_t k = 0; k < d.encoders.size(); ++k)
    ASSERT_EQ(r.dataset.encoders[k].ticks_left, d.encoders[k].ticks_left);
  ASSERT_EQ(r.dataset.scans.size(), d.scans.size());
  // Stamps survive to the nanosecond (1e-9 s) and odometry re-integration is bit-identical
  // input, so the odometry at each scan equals the original to 1e-9 m.
  for (std::size_t k = 0; k < d.scans.size(); ++k) {
    EXPECT_NEAR(r.dataset.scans[k].scan.stamp_s, d.scans[k].scan.stamp_s, 1e-9);
    EXPECT_NEAR(r.dataset.scans[k].T_odom_base_nominal->x, d.scans[k].T_odom_base_nominal->x, 1e-9);
  }
}

// Stale odometry, a held robot and the gyro's heading survive export + import: /joint_states
// carries the held and the turning wheels, /odom the odometry. The import recognises each stale
// hold as missing data (docs/export.md, "Stale odometry") and drops its repeated samples, so
// the catch-up spans the gap; it integrates the joints (heading from the wheels) or keeps /odom
// as logged (the slamprep metadata says its heading is the gyro's).
Dataset faultyRun(const std::string& heading_from) {
  sim::SimConfig c;
  c.scenario = "worlds/scenarios/spin.yaml";
  c.mode = sim::SimMode::kinematic;
  c.lidar.beams_per_revolution = 90;
  c.duration_s = 12.0;
  c.seed = 11;
  sim::applyOverride(c, "faults.enable=stale_odometry,held_robot");
  sim::applyOverride(c, "faults.stale_odometry.rate_hz=1");
  sim::applyOverride(c, "faults.held_robot.rate_hz=0.2");
  sim::applyOverride(c, "odometry.heading_from=" + heading_from);
  Dataset d = sim::simulate(c).dataset;
  EXPECT_FALSE(d.info.faults["stale_odometry"]["events"].empty());
  EXPECT_FALSE(d.info.faults["held_robot"]["events"].empty());
  return d;
}

ImportResult importExport(const Dataset& d) {
  ExportInput in;
  in.dataset = d;
  ImportParams p;  // no --nominal: the bag's metadata has it
  p.ticks_per_revolution = d.info.ticks_per_revolution;
  return importMcap(formatMcap(in, {}), "faults.mcap", p);
}

/// Every sample of `back` equals the one of `original` at its stamp (to the bag's nanosecond);
/// returns the indices of the original's samples that `back` lacks.
template <typename Log, typename Same>
std::vector<std::size_t> missing(const Log& original, const Log& back, Same same) {
  std::vector<std::size_t> out;
  std::size_t j = 0;
  for (std::size_t k = 0; k < original.size(); ++k) {
    if (j < back.size() && std::abs(back[j].stamp_s - original[k].stamp_s) < 1e-9) {
      EXPECT_TRUE(same(original[k], back[j])) << "sample " << k;
      ++j;
    } else {
      out.push_back(k);
    }
  }
  EXPECT_EQ(j, back.size());
  return out;
}

/// The JointState samples the import dropped as stale, checked against the fault's record: every
/// run it found ends with a hold's last sample and holds all of it (a run may start earlier, where
/// the robot stood before the hold with the same ticks), and every hold whose catch-up turned a
/// wheel by more than 0.5 rad (the robot was moving) is found.
std::vector<std::size_t> expectHoldsFound(const Dataset& d, const ImportResult& r) {
  const StaleReport* joints = nullptr;
  for (const StaleReport& report : r.summary.stale)
    if (report.stream.rfind("JointState", 0) == 0) joints = &report;
  EXPECT_NE(joints, nullptr);
  if (!joints) return {};
  const auto& events = d.info.faults["stale_odometry"]["events"];
  const double rad_per_tick = radiansPerTick(d.info.ticks_per_revolution);
  std::vector<std::size_t> dropped;
  for (const StaleRun& run : joints->runs) {
    const bool a_hold = std::any_of(events.begin(), events.end(), [&](const auto& e) {
      const auto k0 = e["sample"].template get<std::size_t>();
      return run.first + 1 <= k0 &&
             run.first + run.repeats + 1 == k0 + e["samples"].template get<std::size_t>();
    });
    EXPECT_TRUE(a_hold) << "stale run at sample " << run.first;
    for (std::size_t k = run.first + 1; k <= run.first + run.repeats; ++k) dropped.push_back(k);
  }
  std::size_t moving = 0;
  for (const auto& e : events) {
    if (!e.contains("jump_ticks")) continue;
    const double jump = rad_per_tick * std::max(std::abs(e["jump_ticks"][0].get<double>()),
                                                std::abs(e["jump_ticks"][1].get<double>()));
    if (jump <= 0.5) continue;
    ++moving;
    const auto k0 = e["sample"].get<std::size_t>(), n = e["samples"].get<std::size_t>();
    EXPECT_TRUE(std::any_of(joints->runs.begin(), joints->runs.end(),
                            [&](const StaleRun& run) {
                              return run.first + 1 <= k0 && run.first + run.repeats + 1 == k0 + n;
                            }))
        << "hold at sample " << k0;
  }
  EXPECT_GE(moving, 3u);
  return dropped;
}

const auto sameTicks = [](const EncoderSample& a, const EncoderSample& b) {
  return a.ticks_left == b.ticks_left && a.ticks_right == b.ticks_right;
};
const auto samePose = [](const Stamped<SE2>& a, const Stamped<SE2>& b) {
  return std::abs(a.value.x - b.value.x) < 1e-9 && std::abs(a.value.y - b.value.y) < 1e-9 &&
         std::abs(normalizeAngle(a.value.yaw - b.value.yaw)) < 1e-9;
};

TEST(SimExport, ImportOfTheExportFindsEveryStaleHoldAndKeepsTheHeldRobotsWheels) {
  const Dataset d = faultyRun("wheels");
  const ImportResult r = importExport(d);
  const Dataset& back = r.dataset;
  EXPECT_FALSE(back.info.config.contains("odometry_heading"));
  // The wheels turning under the held body come through; of the stale holds, the repeats are
  // dropped and nothing else.
  const std::vector<std::size_t> dropped = expectHoldsFound(d, r);
  EXPECT_EQ(missing(d.encoders, back.encoders, sameTicks), dropped);
  // Integrated over each gap, the catch-up lands on the original odometry again.
  EXPECT_EQ(missing(d.odom_nominal.samples(), back.odom_nominal.samples(), samePose), dropped);
}

TEST(SimExport, ImportOfTheExportKeepsTheGyroHeadedOdometry) {
  const Dataset d = faultyRun("gyro");
  const ImportResult r = importExport(d);
  const Dataset& back = r.dataset;
  EXPECT_EQ(back.info.config.value("odometry_heading", ""), "gyro");
  EXPECT_EQ(missing(d.encoders, back.encoders, sameTicks), expectHoldsFound(d, r));
  // /odom as it was: its heading, the gyro's, went on during the holds, so none is dropped.
  EXPECT_TRUE(missing(d.odom_nominal.samples(), back.odom_nominal.samples(), samePose).empty());
  // The wheels' integration would differ: the gyro's heading is what the import must keep.
  const PoseSeries wheels =
      integrateEncoders(d.encoders, d.info.nominal_geometry, d.info.ticks_per_revolution);
  double largest = 0.0;
  for (std::size_t k = 0; k < wheels.size(); ++k)
    largest = std::max(
        largest, std::abs(normalizeAngle(wheels[k].value.yaw - back.odom_nominal[k].value.yaw)));
  EXPECT_GT(largest, 0.1);
}

}  // namespace
}  // namespace slamprep::eval
