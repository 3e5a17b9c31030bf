// The fault models (docs/faults.md): statistics against their parameters, determinism, stream
// independence, faults off leaving the output untouched, glass and floor patches.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/error.hpp"
#include "core/odometry.hpp"
#include "eval/formats/dataset_io.hpp"
#include "sim/drive/fault_injection.hpp"
#include "sim/drive/simulator.hpp"
#include "sim/physics/planar_caster.hpp"
#include "tests/support/scratch_dir.hpp"

namespace slamprep::sim {
namespace {

World squareRoom(double half_m) {
  World world;
  world.name = "square";
  const double c = half_m + 0.1;
  const Eigen::Vector2d corners[4] = {{-c, -c}, {c, -c}, {c, c}, {-c, c}};
  for (int k = 0; k < 4; ++k) world.walls.push_back({corners[k], corners[(k + 1) % 4], 0.2, 2.0});
  return world;
}

Scenario scenario(const std::string& segments_yaml) {
  return parseScenario("segments:\n" + segments_yaml, "test_scenario.yaml");
}

// A long, cheap run: kinematic, standing still, 90 beams, 100 Hz steps.
SimConfig longRun(const std::string& faults, double duration_s = 400.0) {
  SimConfig c;
  c.mode = SimMode::kinematic;
  c.lidar.beams_per_revolution = 90;
  c.physics_rate_hz = 100.0;
  c.duration_s = duration_s;
  c.seed = 11;
  applyOverride(c, "faults.enable=" + faults);
  return c;
}

SimResult run(const SimConfig& c) {
  return simulate(c, squareRoom(3.0), scenario("  - {type: spin, angle_deg: 90}\n"));
}

// A count of a Poisson (or binomial) process is within 4 sigma of its mean.
void expectCount(double count, double mean, const std::string& what) {
  EXPECT_NEAR(count, mean, 4.0 * std::sqrt(mean)) << what;
}

TEST(Faults, NamesParseAndUnknownOnesAreRefused) {
  std::string error;
  EXPECT_FALSE(parseFaultSet("none", &error)->any());
  const auto all = parseFaultSet("all", &error);
  for (const auto& [f, name] : kFaultNames) EXPECT_TRUE(all->has(f)) << name;
  const auto two = parseFaultSet("glass,clock_offset", &error);
  EXPECT_EQ(toString(*two), "clock_offset,glass");
  EXPECT_FALSE(parseFaultSet("glass,ice", &error));
  EXPECT_NE(error.find("unknown fault 'ice'"), std::string::npos) << error;
  SimConfig c;
  EXPECT_THROW(applyOverride(c, "faults.enable=ice"), InputError);
  EXPECT_THROW(applyOverride(c, "faults.dropped_scans.probability=1.5"), InputError);
}

TEST(Faults, OffLeavesTheConfigurationAndTheBytesAsBefore) {
  SimConfig c;
  EXPECT_FALSE(toJson(c).contains("faults"));  // dataset.json's config as before faults
  EXPECT_TRUE(toJson(c, true).contains("faults"));
  applyOverride(c, "faults.enable=clock_offset");
  const nlohmann::json on = toJson(c);
  EXPECT_EQ(on["faults"]["enable"], "clock_offset");
  EXPECT_EQ(toJson(configFromJson(on, "test")), on);

  // Strengths without `enable` change nothing.
  SimConfig plain = longRun("none", 5.0), strong = plain;
  applyOverride(strong, "faults.clock_offset.offset_s=0.1");
  applyOverride(strong, "faults.dropped_beams.probability=0.5");
  const test::ScratchDir root("faults_off");
  eval::writeDataset(root / "a", run(plain).dataset);
  eval::writeDataset(root / "b", run(strong).dataset);
  for (const auto& entry : std::filesystem::directory_iterator(root / "a")) {
    std::ifstream a(entry.path()), b(root / "b" / entry.path().filename());
    std::stringstream sa, sb;
    sa << a.rdbuf();
    sb << b.rdbuf();
    EXPECT_EQ(sa.str(), sb.str()) << entry.path().filename();
    EXPECT_EQ(sa.str().find("\"faults\""), std::string::npos);
  }
}

TEST(Faults, EncoderSpikesHaveTheirRateAndSize) {
  SimConfig c = longRun("encoder_spikes");
  applyOverride(c, "faults.encoder_spikes.rate_hz=1");
  const SimResult clean = run(longRun("none")), faulty = run(c);
  const auto& events = faulty.dataset.info.faults["encoder_spikes"]["events"];
  expectCount(events.size(), 400.0, "spikes in 400 s at 1 Hz");
  ASSERT_EQ(clean.dataset.encoders.size(), faulty.dataset.encoders.size());
  std::size_t differing = 0;
  for (std::size_t k = 0; k < clean.dataset.encoders.size(); ++k) {
    const auto& a = clean.dataset.encoders[k];
    const auto& b = faulty.dataset.encoders[k];
    const std::int64_t d = (b.ticks_left - a.ticks_left) + (b.ticks_right - a.ticks_right);
    if (d != 0) {
      ++differing;
      EXPECT_EQ(std::abs(d) % 500, 0);
    }
  }
  for (const auto& e : events) {
    const auto k = e["sample"].get<std::size_t>();
    const auto& a = clean.dataset.encoders[k];
    const auto& b = faulty.dataset.encoders[k];
    const std::int64_t d =
        e["wheel"] == "left" ? b.ticks_left - a.ticks_left : b.ticks_right - a.ticks_right;
    EXPECT_EQ(std::abs(d) % 500, 0);  // two spikes can fall on one sample
    EXPECT_NE(d, 0);
  }
  EXPECT_LE(differing, events.size());
  EXPECT_GE(differing, events.size() - 5);  // coincident spikes are rare (~0.5 expected)
}

TEST(Faults, EncoderDropoutsRemoveTheirWindows) {
  SimConfig c = longRun("encoder_dropouts");
  applyOverride(c, "faults.encoder_dropouts.rate_hz=0.5");
  applyOverride(c, "faults.encoder_dropouts.duration_s=0.05");
  const SimResult r = run(c);
  const auto& record = r.dataset.info.faults["encoder_dropouts"];
  expectCount(record["events"].size(), 200.0, "dropouts in 400 s at 0.5 Hz");
  const std::size_t clean = 40001;
  EXPECT_EQ(r.dataset.encoders.size(), clean - record["removed"].get<std::size_t>());
  // 5 samples per window, fewer where two windows overlap (rate x duration = 2.5 % of them).
  EXPECT_NEAR(record["removed"].get<double>(), 5.0 * record["events"].size(),
              0.1 * 5.0 * record["events"].size());
  for (const auto& s : r.dataset.encoders)
    for (const auto& e : record["events"])
      EXPECT_FALSE(s.stamp_s >= e["t_from_s"].get<double>() - 1e-9 &&
                   s.stamp_s < e["t_to_s"].get<double>() - 1e-9);
}

TEST(Faults, StampJitterHasItsSigmaAndKeepsTheOrder) {
  const SimResult r = run(longRun("stamp_jitter"));
  auto rms = [](const auto& log, double rate_hz, auto stamp) {
    double sum2 = 0.0, max_abs = 0.0, last = -1e9;
    bool ordered = true;
    for (std::size_t k = 0; k < log.size(); ++k) {
      // The nearest clean stamp: |jitter| < half a period, and a first scan stamped before the
      // first encoder sample is dropped, so k need not be the clean index.
      const double e = stamp(log[k]) - std::round(stamp(log[k]) * rate_hz) / rate_hz;
      sum2 += e * e;
      max_abs = std::max(max_abs, std::abs(e));
      ordered = ordered && stamp(log[k]) > last;
      last = stamp(log[k]);
    }
    EXPECT_TRUE(ordered);
    EXPECT_LE(max_abs, 0.45 / rate_hz + 1e-12);
    return std::sqrt(sum2 / log.size());
  };
  // 40000 encoder samples: the RMS estimate's sigma is 1/sqrt(2n) = 0.35 %; the cut at 4.5
  // sigma removes nothing measurable. 4000 scans: 1.1 %. The IMU's cut at 2.25 sigma (5 ms
  // period) lowers its RMS to 0.97 sigma.
  EXPECT_NEAR(rms(r.dataset.encoders, 100.0, [](const auto& s) { return s.stamp_s; }), 1e-3,
              0.02e-3);
  EXPECT_NEAR(rms(r.dataset.scans, 10.0, [](const auto& s) { return s.scan.stamp_s; }), 1e-3,
              0.05e-3);
  const double imu = rms(r.dataset.imu, 200.0, [](const auto& s) { return s.stamp_s; });
  EXPECT_GT(imu, 0.94e-3);
  EXPECT_LT(imu, 1.0e-3);
}

TEST(Faults, ClockOffsetShiftsEveryScanAndNothingElse) {
  const SimResult clean = run(longRun("none", 20.0)), r = run(longRun("clock_offset", 20.0));
  // The last scan now ends after the last encoder sample and is not kept.
  ASSERT_EQ(clean.dataset.scans.size(), r.dataset.scans.size() + 1);
  for (std::size_t k = 0; k < r.dataset.scans.size(); ++k)
    EXPECT_NEAR(r.dataset.scans[k].scan.stamp_s - clean.dataset.scans[k].scan.stamp_s, 0.005,
                1e-12);
  EXPECT_EQ(clean.dataset.encoders.size(), r.dataset.encoders.size());
  EXPECT_EQ(clean.dataset.encoders.back().stamp_s, r.dataset.encoders.back().stamp_s);
}

TEST(Faults, DroppedScansAndBeamsHaveTheirProbability) {
  SimConfig c = longRun("dropped_scans,dropped_beams");
  applyOverride(c, "faults.dropped_scans.probability=0.1");
  const SimResult clean = run(longRun("none")), r = run(c);
  const auto& faults = r.dataset.info.faults;
  const double scans = clean.dataset.scans.size();
  expectCount(faults["dropped_scans"]["events"].size(), 0.1 * scans, "dropped scans");
  EXPECT_EQ(r.dataset.scans.size() + faults["dropped_scans"]["events"].size(), scans);
  expectCount(faults["dropped_beams"]["count"].get<double>(), 0.005 * 90 * scans, "beams");
  // Every dropped beam of a kept scan reads no return and has no true point.
  std::size_t checked = 0;
  for (const auto& e : faults["dropped_beams"]["events"]) {
    const double t = e["scan"].get<double>() / 10.0;
    for (const auto& rec : r.dataset.scans)
      if (std::abs(rec.scan.stamp_s - t) < 1e-9)
        for (const auto& i : e["beams"]) {
          EXPECT_FALSE(std::isfinite(rec.scan.ranges_m[i.get<std::size_t>()]));
          EXPECT_FALSE(rec.p_ref_true[i.get<std::size_t>()].has_value());
          ++checked;
        }
    if (checked > 200) break;
  }
  EXPECT_GT(checked, 100u);
}

TEST(Faults, ImuBiasDriftIsARandomWalkOfItsStrength) {
  const SimResult clean = run(longRun("none")), r = run(longRun("imu_bias_drift"));
  ASSERT_EQ(clean.dataset.imu.size(), r.dataset.imu.size());
  // Bias = faulty - clean gyro; its steps are N(0, q^2 dt), q = 1e-4, dt = 5 ms.
  double sum2 = 0.0, prev = 0.0;
  const std::size_t n = r.dataset.imu.size();
  for (std::size_t k = 0; k < n; ++k) {
    const double bias = r.dataset.imu[k].gyro_z_radps - clean.dataset.imu[k].gyro_z_radps;
    sum2 += (bias - prev) * (bias - prev);
    prev = bias;
  }
  // 80000 steps: the step sigma is estimated to 0.25 %; 2 % allows rounding of the difference.
  EXPECT_NEAR(std::sqrt(sum2 / (n - 1)), 1e-4 * std::sqrt(0.005), 0.02 * 1e-4 * std::sqrt(0.005));
  EXPECT_NEAR(r.dataset.info.faults["imu_bias_drift"]["final_bias_radps"].get<double>(), prev,
              1e-12);
}

TEST(Faults, SameSeedSameBytesAndOneFaultLeavesAnothersEvents) {
  const SimResult all_a = run(longRun("all", 60.0)), all_b = run(longRun("all", 60.0));
  EXPECT_EQ(all_a.dataset.info.faults.dump(), all_b.dataset.info.faults.dump());
  const test::ScratchDir root("faults_bytes");
  eval::writeDataset(root / "a", all_a.dataset);
  eval::writeDataset(root / "b", all_b.dataset);
  for (const auto& entry : std::filesystem::directory_iterator(root / "a")) {
    std::ifstream a(entry.path()), b(root / "b" / entry.path().filename());
    std::stringstream sa, sb;
    sa << a.rdbuf();
    sb << b.rdbuf();
    EXPECT_EQ(sa.str(), sb.str()) << entry.path().filename();
  }
  for (const auto& [fault, name] : kFaultNames) {
    if (fault == Fault::floor_patches || fault == Fault::glass) continue;  // world faults
    const SimResult alone = run(longRun(std::string(name), 60.0));
    EXPECT_EQ(alone.dataset.info.faults[std::string(name)],
              all_a.dataset.info.faults[std::string(name)])
        << name;
  }
  // Another seed, other events.
  SimConfig other = longRun("all", 60.0);
  other.seed = 12;
  EXPECT_NE(run(other).dataset.info.faults["stamp_jitter"],
            all_a.dataset.info.faults["stamp_jitter"]);
}

TEST(Faults, GlassReturnsNothingOrWhatStandsBehindIt) {
  World world = squareRoom(3.0);
  world.walls.push_back({{1.0, -1.0}, {1.0, 1.0}, 0.02, 2.0});  // pane 1 m ahead of the origin
  world.walls.back().returns = false;
  const PlanarCaster opaque(worldWithFaults(world, FaultSet{})), glass(world);
  const Eigen::Vector2d o(0.0, 0.0), east(1.0, 0.0);
  EXPECT_NEAR(*opaque.cast(o, east, 0.25, 30.0), 0.99, 1e-9);  // the pane's near face
  EXPECT_NEAR(*glass.cast(o, east, 0.25, 30.0), 3.0, 1e-9);    // the wall behind it
  // A glass wall with nothing behind: no return at all.
  World open;
  open.walls.push_back({{1.0, -1.0}, {1.0, 1.0}, 0.02, 2.0, false});
  EXPECT_FALSE(PlanarCaster(open).cast(o, east, 0.25, 30.0));

  // In the simulator: every beam east of the pane sees 3 m with glass on, 0.99 m without.
  SimConfig c = longRun("glass", 1.0);
  const Scenario stop = scenario("  - {type: stop, duration_s: 1}\n");
  auto eastRange = [&](const SimConfig& config) {
    const SimResult r = simulate(config, world, stop);
    const LaserScan& scan = r.dataset.scans.front().scan;
    std::size_t best = 0;  // the beam closest to the base's +x (mount yaw 1 deg)
    for (std::size_t i = 0; i < scan.size(); ++i)
      if (std::abs(scan.beamAngle(i) + config.lidar.T_base_lidar.yaw) <
          std::abs(scan.beamAngle(best) + config.lidar.T_base_lidar.yaw))
        best = i;
    return std::make_pair(scan.ranges_m[best], r.dataset.info.faults);
  };
  const auto [with_glass, record] = eastRange(c);
  EXPECT_NEAR(with_glass, 3.0 - c.lidar.T_base_lidar.x, 0.05);
  EXPECT_EQ(record["glass"]["walls"], nlohmann::json::array({4}));
  EXPECT_NEAR(eastRange(longRun("none", 1.0)).first, 0.99 - c.lidar.T_base_lidar.x, 0.05);
}

TEST(Faults, FloorPatchesMakeTheWheelsSlip) {
  World world = squareRoom(3.0);
  world.T_world_start = SE2(-2.0, 0.0, 0.0);
  // A slippery strip across the path, 1 m to 2 m ahead.
  world.floor_patches.push_back({{{-1.0, -1.0}, {0.0, -1.0}, {0.0, 1.0}, {-1.0, 1.0}}, 0.02});
  const Scenario drive = scenario(
      "  - {type: straight, distance_m: 1.2, speed_mps: 0.5}\n"
      "  - {type: spin, angle_deg: 180, rate_radps: 1.5}\n"
      "  - {type: spin, angle_deg: -180, rate_radps: 1.5}\n");
  auto slip = [&](const std::string& faults) {
    SimConfig c;
    c.lidar.beams_per_revolution = 30;
    applyOverride(c, "faults.enable=" + faults);
    const SimResult r = simulate(c, world, drive);
    return std::make_pair(r.summary.drift_true.final_position_error_m, r.dataset.info.faults);
  };
  const auto [dry, none] = slip("none");
  const auto [wet, record] = slip("floor_patches");
  // Dead reckoning with the TRUE geometry fails only by slip: on the wet strip it is measurable.
  EXPECT_LT(dry, 0.005);
  EXPECT_GT(wet, 5.0 * dry + 0.005) << "dry " << dry << " m, wet " << wet << " m";
  ASSERT_TRUE(record["floor_patches"]["active"].get<bool>());
  const auto& events = record["floor_patches"]["events"];
  ASSERT_GE(events.size(), 2u);
  EXPECT_TRUE(events[0]["entered"].get<bool>());
  // The wheels reach the strip (x = -1) after ~1 m, at 0.5 m/s: after 2 s.
  EXPECT_GT(events[0]["t_s"].get<double>(), 1.9);
}

}  // namespace
}  // namespace slamprep::sim
