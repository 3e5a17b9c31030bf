// The faults real robots showed, simulated, against the commands that must notice them: match
// does not follow an odometry that holds its value and then catches up; calibrate refuses where
// a held robot's wheels turn while the gyro does not; an imported bag's gyro-headed odometry is
// recognised.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "slamprep/algo/agreement/agreement_report.hpp"
#include "slamprep/algo/agreement/dataset_sources.hpp"
#include "slamprep/eval/formats/export.hpp"
#include "slamprep/eval/formats/import.hpp"
#include "slamprep/eval/pipeline/calibration_run.hpp"
#include "slamprep/eval/pipeline/match_trajectory.hpp"
#include "slamprep/sim/drive/config.hpp"
#include "slamprep/sim/drive/simulator.hpp"

namespace slamprep::eval {
namespace {

Dataset simulateWith(const std::vector<std::string>& overrides, double duration_s) {
  sim::SimConfig c;  // default world and drive: figure eight, spins, circles
  c.mode = sim::SimMode::kinematic;
  c.duration_s = duration_s;
  c.seed = 3;
  for (const std::string& o : overrides) sim::applyOverride(c, o);
  return sim::simulate(c).dataset;
}

/// The largest distance and heading error of the matched base poses against the truth, both
/// taken relative to their first pose.
std::pair<double, double> worstError(const Dataset& d, const MatchTrajectory& run) {
  const SE2 truth0 = *d.groundtruth.at(run.T_world_base[0].stamp_s);
  const SE2 match0 = run.T_world_base[0].value;
  double trans = 0.0, rot = 0.0;
  for (const auto& s : run.T_world_base.samples()) {
    const SE2 e = between(between(truth0, *d.groundtruth.at(s.stamp_s)), between(match0, s.value));
    trans = std::max(trans, e.translation().norm());
    rot = std::max(rot, std::abs(e.yaw));
  }
  return {trans, rot};
}

MatchTrajectory track(const Dataset& d, const std::string& deskew, bool single_guess) {
  MatchTrajectoryOptions options;
  if (single_guess) options.params.hypothesis_separation_m = 1e9;
  if (single_guess) options.params.hypothesis_separation_rad = 1e9;
  return matchTrajectory(d, matchScanPoints(d, deskew, false), options);
}

Dataset exportImport(const Dataset& d) {
  ExportInput in;
  in.dataset = d;
  ImportParams p;
  p.ticks_per_revolution = d.info.ticks_per_revolution;
  return importMcap(formatMcap(in, {}), "robot.mcap", p).dataset;
}

// An odometry that holds its value for 0.3-1 s while the robot spins and then catches up (ten
// holds in 40 s). The matcher alone (scans as measured) takes the catch-up as one guess among
// several: its worst heading error stays a fraction of the odometry-only matcher's (5 against 74
// degrees, as measured). Through the whole pipeline the importer drops the held samples and
// match (VICP de-skew) tracks as on a clean log (0.35 degrees, 6 mm).
TEST(SensorFaults, MatchDoesNotFollowAStaleOdometryThatCatchesUp) {
  const Dataset d =
      simulateWith({"faults.enable=stale_odometry", "faults.stale_odometry.rate_hz=0.5"}, 40.0);
  ASSERT_GE(d.info.faults["stale_odometry"]["events"].size(), 5u);
  const double rot = worstError(d, track(d, "none", false)).second;
  const double rot_single = worstError(d, track(d, "none", true)).second;
  EXPECT_GT(rot_single, 5.0 * rot);
  EXPECT_GT(rot_single, 0.5);  // the odometry-only matcher does follow it
  const Dataset imported = exportImport(d);
  const auto [trans, rot_pipeline] = worstError(d, track(imported, "vicp", false));
  EXPECT_LT(trans, 0.02);
  EXPECT_LT(rot_pipeline, 0.02);
}

TEST(SensorFaults, CalibrateRefusesWhereAHeldRobotsWheelsTurn) {
  const Dataset d =
      simulateWith({"faults.enable=held_robot", "faults.held_robot.rate_hz=0.05",
                    "faults.held_robot.min_duration_s=3", "faults.held_robot.max_duration_s=4"},
                   60.0);
  ASSERT_GE(d.info.faults["held_robot"]["events"].size(), 1u);
  DatasetCalibrationParams params;
  params.methods = {algo::CalibrationMethod::kJoint};
  const DatasetCalibration refused = calibrateDataset(params, d);
  ASSERT_FALSE(refused.runs.front().result.ok);
  EXPECT_NE(refused.runs.front().result.reason.find("lifted or blocked"), std::string::npos)
      << refused.runs.front().result.reason;
  params.exclude_disagreement = true;
  const DatasetCalibration kept = calibrateDataset(params, d);
  ASSERT_TRUE(kept.runs.front().result.ok) << kept.runs.front().result.reason;
  EXPECT_NEAR(kept.runs.front().result.geometry.wheel_base_m / d.info.true_geometry->wheel_base_m,
              1.0, 0.003);
}

algo::SensorAgreement importedAgreement(const std::string& heading_from) {
  const Dataset d = simulateWith({"odometry.heading_from=" + heading_from}, 40.0);
  return algo::compareSensors(algo::datasetSources(exportImport(d)));
}

TEST(SensorFaults, AnImportedGyroHeadedOdometryIsRecognised) {
  const algo::SensorAgreement gyro = importedAgreement("gyro");
  ASSERT_EQ(gyro.findings.size(), 1u) << algo::agreementText(gyro);
  EXPECT_NE(gyro.findings[0].find("takes its heading from the gyro"), std::string::npos);
  const algo::SensorAgreement wheels = importedAgreement("wheels");
  EXPECT_TRUE(wheels.findings.empty()) << algo::agreementText(wheels);
}

}  // namespace
}  // namespace slamprep::eval
