// The fault models (docs/faults.md): statistics against their parameters, determinism, stream
// independence, faults off leaving the output untouched, glass and floor patches, stale
// odometry, a held robot, and odometry whose heading is the gyro's.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>

#include "slamprep/core/error.hpp"
#include "slamprep/core/heading.hpp"
#include "slamprep/core/odometry.hpp"
#include "slamprep/eval/formats/dataset_io.hpp"
#include "slamprep/sim/drive/fault_injection.hpp"
#include "slamprep/sim/drive/simulator.hpp"
#include "slamprep/sim/physics/planar_caster.hpp"
#include "slamprep/tests/sim_drive/square_room.hpp"
#include "slamprep/tests/support/scratch_dir.hpp"

namespace slamprep::sim {
namespace {

using test::scenario;
using test::squareRoom;

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
  EXPECT_FALSE(toJson(SimConfig{}).contains("odometry"));  // the wheels' heading: as before
  SimConfig plain = longRun("none", 5.0), strong = plain;
  applyOverride(strong, "faults.clock_offset.offset_s=0.1");
  applyOverride(strong, "faults.dropped_beams.probability=0.5");
  applyOverride(strong, "faults.stale_odometry.rate_hz=5");
  applyOverride(strong, "faults.held_robot.rate_hz=5");
  applyOverride(strong, "faults.read_jitter.encoders_sigma_s=0.05");
  applyOverride(strong, "faults.read_jitter.scans_sigma_s=0.02");
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

// A twin copies a recording whose streams jitter differently: one sigma per stream, the others
// sigma_s. 40000 encoder samples (RMS estimate +-0.35 %; the 10 ms period cuts 2 ms at 2.25
// sigma: 0.978 x 2 ms), 4000 scans (+-1.1 %, cut at 4.5 sigma).
TEST(Faults, StampJitterPerStream) {
  SimConfig c = longRun("stamp_jitter");
  applyOverride(c, "faults.stamp_jitter.encoders_sigma_s=0.002");
  applyOverride(c, "faults.stamp_jitter.scans_sigma_s=0.01");
  const nlohmann::json record = run(c).dataset.info.faults["stamp_jitter"];
  EXPECT_NEAR(record["encoders"]["rms_s"].get<double>(), 1.956e-3, 0.04e-3);
  EXPECT_NEAR(record["scans"]["rms_s"].get<double>(), 10e-3, 0.5e-3);
  // The IMU keeps sigma_s (1 ms; its 5 ms period cuts it at 2.25 sigma: 0.97 ms).
  EXPECT_NEAR(record["imu"]["rms_s"].get<double>(), 0.97e-3, 0.03e-3);
  SimConfig bad = c;
  EXPECT_THROW(applyOverride(bad, "faults.stamp_jitter.scans_sigma_s=-0.5"), std::exception);
}

// Sampled off the grid and stamped off that (a twin of a host-stamped robot gets both), the two
// draws together stay within 0.45 periods of the grid, as each does alone: 40 % of a period each
// would otherwise swap neighbours (their difference exceeds a period 5 % of the time).
TEST(Faults, SamplingAndStampJitterTogetherKeepTheOrder) {
  SimConfig c = longRun("stamp_jitter", 100.0);
  applyOverride(c, "faults.stamp_jitter.encoders_sigma_s=0.004");
  applyOverride(c, "faults.stamp_jitter.encoders_sampling_sigma_s=0.004");
  const SimResult r = run(c);
  const auto& e = r.dataset.encoders;
  ASSERT_GT(e.size(), 9000u);
  double max_off = 0.0;
  for (std::size_t k = 1; k < e.size(); ++k) {
    ASSERT_GT(e[k].stamp_s, e[k - 1].stamp_s) << k;
    max_off = std::max(max_off, std::abs(e[k].stamp_s - std::round(e[k].stamp_s * 100.0) / 100.0));
  }
  EXPECT_LE(max_off, 0.0045 + 1e-12);
  EXPECT_GT(max_off, 0.004);  // the bound is reached: the draws do add up
}

/// When each left-wheel sample of `d` was read, against the clean log: its ticks off the clean
/// ones over the wheel's ticks per second (after the 5 s ramp-up, where the rate is constant).
std::vector<double> readErrors(const Dataset& d, const Dataset& clean) {
  const auto& cl = clean.encoders;
  std::vector<double> e;
  for (std::size_t k = 1; k + 1 < d.encoders.size(); ++k) {
    EXPECT_EQ(d.encoders[k].stamp_s, cl[k].stamp_s);
    if (cl[k].stamp_s < 5.0) continue;
    const double ticks_per_s = double(cl[k + 1].ticks_left - cl[k - 1].ticks_left) /
                               (cl[k + 1].stamp_s - cl[k - 1].stamp_s);
    e.push_back(double(d.encoders[k].ticks_left - cl[k].ticks_left) / ticks_per_s);
  }
  return e;
}

double rms(const std::vector<double>& e) {
  double sum2 = 0.0;
  for (double x : e) sum2 += x * x;
  return std::sqrt(sum2 / double(e.size()));
}

/// The read jitter's run on the arc, and the same run without faults.
std::pair<Dataset, Dataset> readJitterRun(const std::string& sigma, const std::string& tau) {
  SimConfig c = longRun("read_jitter", 40.0);
  applyOverride(c, "faults.read_jitter.encoders_sigma_s=" + sigma);
  applyOverride(c, "faults.read_jitter.encoders_correlation_s=" + tau);
  const Scenario arc = scenario("  - {type: arc, v_mps: 0.3, w_radps: 0.8, duration_s: 45}\n");
  SimConfig off = c;
  applyOverride(off, "faults.enable=none");
  return {simulate(c, squareRoom(3.0), arc).dataset, simulate(off, squareRoom(3.0), arc).dataset};
}

// Read jitter on an arc of constant wheel rates: every stamp stays on its grid, and what each
// sample is off the clean log, in ticks over the wheel's ticks per second, is when it was read.
// 3500 samples after the ramp-up.
TEST(Faults, ReadJitterKeepsTheStampsAndReadsTheWheelsOffThem) {
  const auto [d, clean] = readJitterRun("0.005", "0");
  ASSERT_EQ(d.encoders.size(), clean.encoders.size());
  const std::vector<double> e = readErrors(d, clean);
  ASSERT_GT(e.size(), 3000u);
  const nlohmann::json& record = d.info.faults["read_jitter"];
  const double drawn_rms = record["encoders"]["rms_s"].get<double>();
  EXPECT_NEAR(drawn_rms, 5e-3, 0.2e-3);  // 4000 draws: +-0.056 ms
  // The ticks' rounding adds under 0.2 ms at about 2000 ticks/s.
  EXPECT_NEAR(rms(e), drawn_rms, 0.2e-3);
  EXPECT_EQ(record["encoders_sigma_s"], 0.005);
  EXPECT_EQ(record["encoders"]["count"], d.encoders.size());
  EXPECT_FALSE(record.contains("scans"));  // scans_sigma_s is 0 by default
  SimConfig off = longRun("read_jitter", 40.0);
  EXPECT_THROW(applyOverride(off, "faults.read_jitter.encoders_sigma_s=-1"), std::exception);
  EXPECT_THROW(applyOverride(off, "faults.read_jitter.encoders_correlation_s=-1"), std::exception);
}

// Correlated over 0.5 s, the read errors keep their sigma and follow an AR(1): neighbouring
// samples (10 ms apart at 100 Hz) correlate exp(-0.02) = 0.98, samples 0.5 s apart exp(-1) =
// 0.37. 40 s hold about 80 independent stretches, so the RMS is good to about +-15 %.
TEST(Faults, ReadJitterCorrelatedOverTimeKeepsItsSigma) {
  const auto [d, clean] = readJitterRun("0.005", "0.5");
  const std::vector<double> e = readErrors(d, clean);
  ASSERT_GT(e.size(), 3000u);
  EXPECT_NEAR(rms(e), 5e-3, 0.15 * 5e-3);
  const auto correlation = [&](std::size_t lag) {
    double xy = 0.0;
    for (std::size_t k = lag; k < e.size(); ++k) xy += e[k] * e[k - lag];
    return xy / double(e.size() - lag) / (rms(e) * rms(e));
  };
  const double step = clean.encoders[1].stamp_s - clean.encoders[0].stamp_s;
  EXPECT_NEAR(correlation(1), std::exp(-step / 0.5), 0.02);
  EXPECT_NEAR(correlation(std::size_t(std::lround(0.5 / step))), std::exp(-1.0), 0.15);
}

// The scans' side: stamped on their grid, taken when the record says. A scan's true pose is
// the truth's at its stamp plus its error, to under 1 mm (the truth's samples interpolated),
// where at its stamp it would be 6 mm off (0.3 m/s x 20 ms); the errors have their sigma: 400
// scans, RMS estimate +-3.5 %.
TEST(Faults, ReadJitterTakesTheScansOffTheirStamps) {
  SimConfig c = longRun("read_jitter", 40.0);
  applyOverride(c, "faults.read_jitter.encoders_sigma_s=0");
  applyOverride(c, "faults.read_jitter.scans_sigma_s=0.02");
  const Scenario arc = scenario("  - {type: arc, v_mps: 0.3, w_radps: 0.8, duration_s: 45}\n");
  const Dataset d = simulate(c, squareRoom(3.0), arc).dataset;
  const nlohmann::json& record = d.info.faults["read_jitter"]["scans"];
  const auto errors = record["errors_s"].get<std::vector<double>>();
  ASSERT_GE(errors.size(), d.scans.size());
  EXPECT_NEAR(record["rms_s"].get<double>(), 0.02, 0.0025);
  double worst_stamp = 0.0, worst_pose = 0.0, sum2_at_stamp = 0.0;
  for (std::size_t k = 0; k < d.scans.size(); ++k) {
    const double grid = double(k) / c.lidar.rate_hz;
    worst_stamp = std::max(worst_stamp, std::abs(d.scans[k].scan.stamp_s - grid));
    const auto T = d.groundtruth.at(grid + errors[k]);
    ASSERT_TRUE(T && d.scans[k].T_world_base_true);
    const Eigen::Vector2d p_true = d.scans[k].T_world_base_true->translation();
    worst_pose = std::max(worst_pose, (T->translation() - p_true).norm());
    sum2_at_stamp += (d.groundtruth.at(grid)->translation() - p_true).squaredNorm();
  }
  EXPECT_LT(worst_stamp, 1e-9);
  EXPECT_LT(worst_pose, 1e-3);
  EXPECT_GT(std::sqrt(sum2_at_stamp / double(d.scans.size())), 5e-3);
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

// A lidar whose housing blocks a quarter of its view and which returns half of its far beams:
// no return in the blocked bins, every near beam elsewhere, half of the far ones (binomial).
TEST(Faults, DroppedBeamsFollowTheirAngleAndRangeProfiles) {
  SimConfig c = longRun("dropped_beams", 100.0);
  applyOverride(c, "faults.dropped_beams.probability=0");
  applyOverride(c, "faults.dropped_beams.by_angle=0,1,1,1");  // [-180, -90) deg blocked
  applyOverride(c, "faults.dropped_beams.by_range=1,1,1,1,0.5");
  applyOverride(c, "faults.dropped_beams.range_bin_m=0.4");  // half from 1.6 m on
  const SimResult clean = run(longRun("none", 100.0)), shaped = run(c);
  ASSERT_EQ(clean.dataset.scans.size(), shaped.dataset.scans.size());
  std::size_t blocked_returns = 0, near_lost = 0, far = 0, far_kept = 0;
  for (std::size_t k = 0; k < clean.dataset.scans.size(); ++k) {
    const LaserScan &a = clean.dataset.scans[k].scan, &b = shaped.dataset.scans[k].scan;
    for (std::size_t i = 0; i < a.size(); ++i) {
      if (!a.valid(i)) continue;
      const double angle = std::remainder(a.beamAngle(i), 2 * std::numbers::pi);
      if (angle < -std::numbers::pi / 2) {
        blocked_returns += b.valid(i);
      } else if (a.ranges_m[i] < 1.6) {
        near_lost += !b.valid(i);
      } else {
        ++far;
        far_kept += b.valid(i);
      }
    }
  }
  EXPECT_EQ(blocked_returns, 0U);
  EXPECT_EQ(near_lost, 0U);
  ASSERT_GT(far, 1000U);
  expectCount(double(far_kept), 0.5 * double(far), "far beams kept");
  const auto& record = shaped.dataset.info.faults["dropped_beams"];
  EXPECT_EQ(record["by_angle"], "0,1,1,1");
  EXPECT_DOUBLE_EQ(record["range_bin_m"].get<double>(), 0.4);
  EXPECT_THROW(applyOverride(c, "faults.dropped_beams.by_angle=1,x"), InputError);
  EXPECT_THROW(applyOverride(c, "faults.dropped_beams.by_range=-1"), InputError);
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

// ---- Stale odometry, a held robot, the gyro's heading ---------------------------------------

namespace slamprep::sim {
namespace {

double yawChange(const SE2& a, const SE2& b) {
  return std::abs(normalizeAngle(b.yaw - a.yaw));
}

TEST(Faults, StaleOdometryHoldsItsPoseThenJumpsByTheTruthsMotion) {
  SimConfig c = longRun("stale_odometry", 40.0);
  applyOverride(c, "faults.stale_odometry.rate_hz=0.3");
  c.nominal = {0.0, 0.0, 0.0};  // the odometry's geometry is the truth's: it errs by ticks only
  // One arc of constant curvature: the catch-up step's single arc is the truth's motion.
  const Scenario arc = scenario("  - {type: arc, v_mps: 0.3, w_radps: 0.8, duration_s: 45}\n");
  const SimResult r = simulate(c, squareRoom(3.0), arc);
  const Dataset& d = r.dataset;
  ASSERT_EQ(d.odom_nominal.size(), d.encoders.size());
  SimConfig clean = c;
  applyOverride(clean, "faults.enable=none");
  EXPECT_EQ(d.scans.size(), simulate(clean, squareRoom(3.0), arc).dataset.scans.size());

  std::size_t checked = 0;
  for (const auto& e : d.info.faults["stale_odometry"]["events"]) {
    const auto k0 = e["sample"].get<std::size_t>(), k1 = k0 + e["samples"].get<std::size_t>();
    EXPECT_NEAR(e["t_to_s"].get<double>() - e["t_from_s"].get<double>(), 0.65, 0.35 + 1e-12);
    if (!e.contains("jump_ticks") || e["t_from_s"].get<double>() < 1.0) continue;  // ramp-up
    // The odometry repeats the last pose before the hold, bit for bit, over all of it.
    const SE2& held = d.odom_nominal[k0 - 1].value;
    for (std::size_t k = k0; k < k1; ++k) {
      EXPECT_EQ(d.odom_nominal[k].value.x, held.x);
      EXPECT_EQ(d.odom_nominal[k].value.y, held.y);
      EXPECT_EQ(d.odom_nominal[k].value.yaw, held.yaw);
    }
    // ... while the truth turns at least 0.3 s x 0.8 rad/s ...
    const SE2 truth0 = *d.groundtruth.at(d.encoders[k0 - 1].stamp_s);
    const SE2 truth_held = *d.groundtruth.at(d.encoders[k1 - 1].stamp_s);
    const SE2 truth1 = *d.groundtruth.at(d.encoders[k1].stamp_s);
    EXPECT_GT(yawChange(truth0, truth_held), 0.2);
    // ... and then jumps by the truth's motion since the hold began, up to the ticks (1 tick =
    // 0.15 mm of wheel travel, 3e-4 rad of heading).
    const SE2 jump = between(d.odom_nominal[k1 - 1].value, d.odom_nominal[k1].value);
    const SE2 moved = between(truth0, truth1);
    EXPECT_LT((jump.translation() - moved.translation()).norm(), 1e-3);
    EXPECT_LT(yawChange(jump, moved), 1e-3);
    const auto& ticks = e["jump_ticks"];
    EXPECT_EQ(ticks[0].get<std::int64_t>(),
              d.encoders[k1].ticks_left - d.encoders[k0 - 1].ticks_left);
    ++checked;
  }
  EXPECT_GE(checked, 5u);  // ~11 holds in 40 s at 0.3 Hz
}

/// The held robot's signature: during every event (away from its edges) the truth and the
/// integrated gyro stand still while the encoders integrate a turn of more than 1.5 rad.
std::size_t expectHeldSignature(const Dataset& d, double truth_tolerance) {
  const DiffDriveParams& g = *d.info.true_geometry;
  const double rad_per_tick = radiansPerTick(d.info.ticks_per_revolution);
  std::size_t checked = 0;
  for (const auto& e : d.info.faults["held_robot"]["events"]) {
    const double a = e["t_from_s"].get<double>() + 0.05, b = e["t_to_s"].get<double>() - 0.05;
    if (b > d.encoders.back().stamp_s) continue;
    const SE2 truth_a = *d.groundtruth.at(a), truth_b = *d.groundtruth.at(b);
    EXPECT_LT(yawChange(truth_a, truth_b), truth_tolerance) << "held at " << a;
    EXPECT_LT((truth_b.translation() - truth_a.translation()).norm(), truth_tolerance);
    // bias 1 mrad/s, noise: < 4 mrad in 3 s
    EXPECT_LT(std::abs(*turned(gyroHeading(d.imu), a, b, 0.1)), 0.01);
    // The encoders' turn over the samples inside [a, b], with the TRUE geometry.
    const auto inside = [&](double t) {
      return std::lower_bound(d.encoders.begin(), d.encoders.end(), t,
                              [](const EncoderSample& s, double v) { return s.stamp_s < v; });
    };
    const EncoderSample &ea = *inside(a), &eb = *(inside(b) - 1);
    const double wheel_yaw = g.twist((eb.ticks_left - ea.ticks_left) * rad_per_tick,
                                     (eb.ticks_right - ea.ticks_right) * rad_per_tick)
                                 .y();
    EXPECT_GT(std::abs(wheel_yaw), 1.5);
    ++checked;
  }
  return checked;
}

SimConfig heldRun(SimMode mode, double duration_s, double rate_hz) {
  SimConfig c = longRun("held_robot", duration_s);
  c.mode = mode;
  if (mode == SimMode::physics) c.physics_rate_hz = 1000.0;
  applyOverride(c, "faults.held_robot.rate_hz=" + std::to_string(rate_hz));
  applyOverride(c, "faults.held_robot.min_duration_s=2");
  applyOverride(c, "faults.held_robot.max_duration_s=3");
  return c;
}

const Scenario& longSpin() {
  static const Scenario s = scenario("  - {type: spin, angle_deg: 2000, rate_radps: 1.0}\n");
  return s;
}

TEST(Faults, HeldRobotsWheelsTurnWhileTheBodyAndTheGyroStandStill) {
  const SimResult r = simulate(heldRun(SimMode::kinematic, 30.0, 0.1), squareRoom(3.0), longSpin());
  EXPECT_GE(expectHeldSignature(r.dataset, 1e-12), 2u);  // kinematic: the body does not move
  // Outside the events the robot turns: the truth turned the commanded angle less the holds.
  double held_s = 0.0;
  for (const auto& e : r.dataset.info.faults["held_robot"]["events"])
    held_s += std::min(30.0, e["t_to_s"].get<double>()) - e["t_from_s"].get<double>();
  EXPECT_GT(held_s, 4.0);
  EXPECT_GT(r.summary.rotation_rad, 30.0 - held_s - 2.0);
  EXPECT_LT(r.summary.rotation_rad, 1.0377 * (30.0 - held_s) + 0.1);
}

TEST(Faults, HeldRobotInThePhysicsSkidsItsWheelsUnderAStillChassis) {
  const SimResult r = simulate(heldRun(SimMode::physics, 14.0, 0.3), squareRoom(3.0), longSpin());
  EXPECT_GE(expectHeldSignature(r.dataset, 1e-3), 1u);
  // Let go, the robot turns again.
  const auto& events = r.dataset.info.faults["held_robot"]["events"];
  ASSERT_FALSE(events.empty());
  const double after = events[0]["t_to_s"].get<double>() + 0.5;
  if (after + 1.0 < 14.0) {
    EXPECT_GT(yawChange(*r.dataset.groundtruth.at(after), *r.dataset.groundtruth.at(after + 1.0)),
              0.5);
  }
}

TEST(Faults, HeldWindowsStopTheKinematicBody) {
  SimConfig c = heldRun(SimMode::kinematic, 30.0, 0.1);
  const HeldSchedule held(c.faults, c.seed, 30.0);
  ASSERT_FALSE(held.windows().empty());
  const Controller controller(longSpin().profile, c.nominalGeometry());
  const TimeWindow w = held.windows().front();
  const DiffDriveParams& g = c.robot.geometry;
  // Inside a window: no motion; across its start: the arc of the part before it.
  const SE2 none = held.bodyIncrement(controller, g, w.from_s + 0.1, w.from_s + 0.2);
  EXPECT_EQ(none.yaw, 0.0);
  EXPECT_EQ(none.x, 0.0);
  const Eigen::Vector2d dphi = controller.wheelAngleIncrement(w.from_s - 0.05, w.from_s);
  EXPECT_NEAR(held.bodyIncrement(controller, g, w.from_s - 0.05, w.from_s + 0.05).yaw,
              wheelIncrement(g, dphi.x(), dphi.y()).yaw, 1e-15);
  EXPECT_FALSE(held.heldAt(w.from_s - 1e-9));
  EXPECT_TRUE(held.heldAt(w.from_s));
  EXPECT_FALSE(held.heldAt(w.to_s));
}

TEST(OdometryHeading, GyroHeadingIsTheIntegratedGyroAndTheWheelsTranslation) {
  const Scenario drive = scenario(
      "  - {type: spin, angle_deg: 360}\n"
      "  - {type: arc, v_mps: 0.3, w_radps: 0.5, duration_s: 10}\n");
  SimConfig c = longRun("none", 17.0);
  const SimResult by_wheels = simulate(c, squareRoom(3.0), drive);
  applyOverride(c, "odometry.heading_from=gyro");
  const SimResult by_gyro = simulate(c, squareRoom(3.0), drive);
  const Dataset& d = by_gyro.dataset;
  EXPECT_EQ(d.info.config.value("odometry_heading", ""), "gyro");
  EXPECT_FALSE(by_wheels.dataset.info.config.contains("odometry_heading"));
  // encoders.csv stays the wheels' ticks.
  ASSERT_EQ(d.encoders.size(), by_wheels.dataset.encoders.size());
  for (std::size_t k = 0; k < d.encoders.size(); ++k) {
    ASSERT_EQ(d.encoders[k].ticks_left, by_wheels.dataset.encoders[k].ticks_left);
    ASSERT_EQ(d.encoders[k].ticks_right, by_wheels.dataset.encoders[k].ticks_right);
  }
  ASSERT_EQ(d.odom_nominal.size(), d.encoders.size());
  // Heading: the gyro's trapezoids summed from the first encoder stamp, to rounding (every
  // encoder stamp k / 100 is the IMU stamp 2k / 200).
  const DiffDriveParams& nominal = d.info.nominal_geometry;
  const double rad_per_tick = radiansPerTick(d.info.ticks_per_revolution);
  double worst_yaw = 0.0, worst_distance = 0.0, gyro_yaw = 0.0;
  std::size_t j = 0;  // IMU sample at the encoder stamp
  for (std::size_t k = 1; k < d.encoders.size(); ++k) {
    for (; d.imu[j].stamp_s < d.encoders[k].stamp_s; ++j)
      gyro_yaw += 0.5 * (d.imu[j].gyro_z_radps + d.imu[j + 1].gyro_z_radps) *
                  (d.imu[j + 1].stamp_s - d.imu[j].stamp_s);
    ASSERT_EQ(d.imu[j].stamp_s, d.encoders[k].stamp_s);
    worst_yaw = std::max(worst_yaw, yawChange(SE2(0, 0, gyro_yaw), d.odom_nominal[k].value));
    // Translation: the wheels' distance of the step along an arc, nothing sideways.
    const auto &a = d.encoders[k - 1], &b = d.encoders[k];
    const double s = nominal
                         .twist((b.ticks_left - a.ticks_left) * rad_per_tick,
                                (b.ticks_right - a.ticks_right) * rad_per_tick)
                         .x();
    const Eigen::Vector3d step =
        between(d.odom_nominal[k - 1].value, d.odom_nominal[k].value).log();
    worst_distance = std::max({worst_distance, std::abs(step.x() - s), std::abs(step.y())});
  }
  EXPECT_LT(worst_yaw, 1e-9);
  EXPECT_LT(worst_distance, 1e-12);
  // With the wheel base 4 % too long, the wheels' heading is 13.6 deg short per commanded turn
  // and the arc's; the gyro's follows the truth up to its bias (1 mrad/s) and noise.
  const SE2 truth_end = *d.groundtruth.at(d.encoders.back().stamp_s);
  const double wheel_error =
      yawChange(by_wheels.dataset.odom_nominal.samples().back().value, truth_end);
  const double gyro_error = yawChange(d.odom_nominal.samples().back().value, truth_end);
  EXPECT_GT(wheel_error, 0.2);
  EXPECT_LT(gyro_error, 0.03);
}

TEST(Faults, StaleHeldAndGyroHeadingSameSeedSameBytesInThePhysics) {
  auto write = [](const std::filesystem::path& dir) {
    SimConfig c = heldRun(SimMode::physics, 8.0, 0.3);
    applyOverride(c, "faults.enable=stale_odometry,held_robot");
    applyOverride(c, "faults.stale_odometry.rate_hz=1");
    applyOverride(c, "odometry.heading_from=gyro");
    const SimResult r = simulate(c, squareRoom(3.0), longSpin());
    EXPECT_FALSE(r.dataset.info.faults["stale_odometry"]["events"].empty());
    EXPECT_FALSE(r.dataset.info.faults["held_robot"]["events"].empty());
    eval::writeDataset(dir, r.dataset);
  };
  const test::ScratchDir root("faults_new_bytes");
  write(root / "a");
  write(root / "b");
  for (const auto& entry : std::filesystem::directory_iterator(root / "a")) {
    std::ifstream a(entry.path()), b(root / "b" / entry.path().filename());
    std::stringstream sa, sb;
    sa << a.rdbuf();
    sb << b.rdbuf();
    EXPECT_EQ(sa.str(), sb.str()) << entry.path().filename();
  }
}

}  // namespace
}  // namespace slamprep::sim
