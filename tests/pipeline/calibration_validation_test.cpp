// calibrate --validate-fraction: the held-out error's definition on a drive computed by hand,
// and on a short simulated drive the calibrated geometry beating the simulator's deliberately
// wrong nominal one (r_L +2 %, r_R -1.5 %, b +4 %) on scans the calibration never saw.
#include "slamprep/eval/pipeline/calibration_validation.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <regex>

#include "slamprep/core/error.hpp"
#include "slamprep/eval/formats/dataset_io.hpp"
#include "slamprep/eval/pipeline/recordings_calibration.hpp"
#include "slamprep/sim/drive/simulator.hpp"
#include "slamprep/tests/support/scratch_dir.hpp"

namespace slamprep::eval {
namespace {

// Straight at 0.1 m/s for 30 s: both wheels at 1 rad/s with r = 0.1 m, 4096 ticks, 10 Hz.
OdometryEncoders straightEncoders() {
  OdometryEncoders e;
  e.source = "straight";
  e.ticks_per_revolution = 4096;
  for (int k = 0; k <= 300; ++k) {
    const double t = 0.1 * k;
    const auto ticks =
        static_cast<std::int64_t>(std::llround(t / (2.0 * std::numbers::pi) * 4096.0));
    e.encoders.push_back({t, ticks, ticks});
  }
  return e;
}

// A radius 2 % long makes every 10 s window 2 % of 1 m long: 0.02 m, whatever the start; the
// starts are the scans 0 .. 20 s (1 Hz) whose 10 s end lies in the part.
TEST(HeldOutError, TenSecondWindowsOfAStraightDriveByHand) {
  HeldOutPart part;
  part.odometry = straightEncoders();
  const DiffDriveParams truth{0.1, 0.1, 0.5};
  const PoseSeries exact = integrateOdometry(part.odometry, truth);
  for (int s = 0; s <= 30; ++s) {
    part.stamps_s.push_back(s);
    part.T_world_lidar.push_back(*exact.at(s) * SE2(0.2, 0.0, 0.0));
  }
  const SE2 mount(0.2, 0.0, 0.0);
  const algo::HeldOutError none = heldOutError(part, truth, mount);
  EXPECT_LT(none.trans_m, 1e-12);
  const algo::HeldOutError scaled = heldOutError(part, {0.102, 0.102, 0.5}, mount);
  // Tick quantisation moves each window's length by less than one tick (0.15 mm x 2 %).
  EXPECT_NEAR(scaled.trans_m, 0.02, 1e-5);
  EXPECT_LT(scaled.rot_deg, 1e-9);
  // A part shorter than one window: one window over all of it (5 s: 0.5 m, 0.01 m error).
  part.stamps_s.resize(6);
  part.T_world_lidar.resize(6);
  EXPECT_NEAR(heldOutError(part, {0.102, 0.102, 0.5}, mount).trans_m, 0.01, 1e-5);
}

TEST(ValidationSplit, HoldsOutTheLastFractionOfTheScansByTime) {
  Dataset d;
  for (int k = 0; k < 10; ++k) {
    ScanRecord r;
    r.scan.stamp_s = 1.0 + k;
    d.scans.push_back(r);
  }
  const ValidationSplit split = splitForValidation(d, 0.3, "d");
  EXPECT_DOUBLE_EQ(split.t_split_s, 1.0 + 0.7 * 9.0);
  EXPECT_EQ(split.calibration.scans.size(), 7u);              // 1 .. 7 s
  EXPECT_EQ(split.held_out.scans.size(), 3u);                 // 8 .. 10 s
  EXPECT_THROW(splitForValidation(d, 0.1, "d"), InputError);  // one scan held out
  EXPECT_THROW(splitForValidation(d, 1.0, "d"), InputError);
}

// The figure eight (25 s, both curvatures in the first 70 %), its last 30 % held out: 7.5 s of
// the right-hand circle, where the wrong nominal geometry turns about 3.75 % too little.
TEST(CalibrationValidation, CalibratedBeatsTheWrongNominalOnHeldOutScans) {
  sim::SimConfig config;
  config.scenario = "worlds/scenarios/figure_eight.yaml";
  config.mode = sim::SimMode::kinematic;
  const test::ScratchDir scratch("calibration_validation");
  const auto dir = scratch / "data";
  writeDataset(dir, sim::simulate(config).dataset);

  RecordingsCalibrationParams params;
  params.datasets = {dir.string()};
  params.base.methods = {algo::CalibrationMethod::kJoint};
  params.validate_fraction = 0.3;
  const RecordingsCalibration r = calibrateRecordings(params);
  ASSERT_EQ(r.report.recordings.size(), 1u);
  const algo::MethodReport& joint = r.report.recordings[0].methods.at(0);
  ASSERT_TRUE(joint.run.result.ok) << joint.run.result.reason;
  ASSERT_TRUE(joint.validation);
  const algo::ValidationFigures& v = *joint.validation;
  EXPECT_EQ(v.fraction, 0.3);
  // Measured: raw 0.16 m, 8.0 deg; joint 0.013 m, 1.2 deg, which is also what the true
  // geometry scores: the scan-to-map reference's own error over the part.
  EXPECT_GT(v.raw.rot_deg, 4.0);
  EXPECT_LT(v.calibrated.rot_deg, 0.25 * v.raw.rot_deg);
  EXPECT_LT(v.calibrated.trans_m, 0.25 * v.raw.trans_m);
  // joint estimates the mount, so its wheels are also scored with the dataset's mount: better
  // than raw as well, and with the same rotation error (a mount does not change relative yaw).
  ASSERT_TRUE(v.calibrated_wheels);
  EXPECT_LT(v.calibrated_wheels->trans_m, 0.25 * v.raw.trans_m);
  EXPECT_NEAR(v.calibrated_wheels->rot_deg, v.calibrated.rot_deg, 1e-9);
  // The calibration saw none of the held-out scans.
  const Dataset d = readDataset(dir);
  const double t0 = d.scans.front().scan.stamp_s, t1 = d.scans.back().scan.stamp_s;
  EXPECT_LT(r.recordings[0].calibration.intervals.intervals.back().t_end_s, t0 + 0.7 * (t1 - t0));
  EXPECT_GT(r.recordings[0].held_out->stamps_s.size(), 50u);
}

// The figure eight imported as if its tf put the lidar 15 cm beside where it is: the joint
// method finds the lidar where it is, the fit contradicts the mount given with the recording,
// which is then neither fused as a prior nor kept quiet: it is flagged. With the tf right, the
// prior is fused and nothing is flagged. A simulated dataset (no "lidar_mount_from") has no
// prior and is never compared.
TEST(CalibrationValidation, AMountFarFromTheRecordingsTfIsFlaggedNotFused) {
  sim::SimConfig config;
  config.scenario = "worlds/scenarios/figure_eight.yaml";
  config.mode = sim::SimMode::kinematic;
  const test::ScratchDir scratch("calibration_mount_flag");
  Dataset d = sim::simulate(config).dataset;
  writeDataset(scratch / "simulated", d);
  d.info.config["lidar_mount_from"] = "tf base_link -> laser";
  writeDataset(scratch / "right", d);
  d.info.T_base_lidar = d.info.T_base_lidar * SE2(0.0, 0.15, 0.0);
  writeDataset(scratch / "wrong", d);

  auto joint = [&](const char* name) {
    RecordingsCalibrationParams params;
    params.datasets = {(scratch / name).string()};
    params.base.methods = {algo::CalibrationMethod::kJoint};
    const algo::MethodReport m = calibrateRecordings(params).report.recordings[0].methods[0];
    EXPECT_TRUE(m.run.result.ok) << m.run.result.reason;
    return m;
  };
  auto mountFlags = [](const algo::MethodReport& m) {
    std::vector<std::string> causes;
    for (const algo::NominalFlag& f : m.flags)
      if (f.param == "lidar_mount") causes.push_back(f.likely_cause);
    return causes;
  };
  EXPECT_FALSE(joint("simulated").run.mount_prior);

  const algo::MethodReport right = joint("right");
  ASSERT_TRUE(right.run.mount_prior);
  EXPECT_TRUE(right.run.mount_prior->applied);
  EXPECT_LT(right.run.mount_prior->chi2, 14.16);
  EXPECT_TRUE(mountFlags(right).empty());

  const algo::MethodReport wrong = joint("wrong");
  ASSERT_TRUE(wrong.run.mount_prior);
  EXPECT_FALSE(wrong.run.mount_prior->applied);
  EXPECT_GT(wrong.run.mount_prior->chi2, 14.16);
  const std::vector<std::string> causes = mountFlags(wrong);
  ASSERT_EQ(causes.size(), 1u);
  // Measured 151 mm (the joint mount's own error is about 1 mm here).
  EXPECT_TRUE(std::regex_search(causes[0], std::regex(" 1(4[7-9]|5[0-3]) mm and "))) << causes[0];
  EXPECT_NE(causes[0].find("tf base_link -> laser"), std::string::npos);
  EXPECT_NE(causes[0].find("suspect"), std::string::npos) << causes[0];
}

// The figure eight told a geometry 2 % large in r_L, r_R and b alike (as a lidar reading 2 %
// short would make it look): flagged as a range scale, which the simulator's usual wrong nominal
// (r_L +2 %, r_R -1.5 %, b +4 %) is not.
TEST(CalibrationValidation, AGeometryOffByOneFactorIsFlaggedAsARangeScale) {
  const test::ScratchDir scratch("calibration_scale_flag");
  auto flags = [&](const char* name, double error) {
    sim::SimConfig config;
    config.scenario = "worlds/scenarios/figure_eight.yaml";
    config.mode = sim::SimMode::kinematic;
    if (error != 0.0) config.nominal = {error, error, error};
    writeDataset(scratch / name, sim::simulate(config).dataset);
    RecordingsCalibrationParams params;
    params.datasets = {(scratch / name).string()};
    params.base.methods = {algo::CalibrationMethod::kJoint};
    const algo::MethodReport m = calibrateRecordings(params).report.recordings[0].methods[0];
    EXPECT_TRUE(m.run.result.ok) << m.run.result.reason;
    std::vector<algo::NominalFlag> out;
    for (const algo::NominalFlag& f : m.flags)
      if (f.param == "range_scale") out.push_back(f);
    return out;
  };
  const std::vector<algo::NominalFlag> one_factor = flags("one_factor", 0.02);
  ASSERT_EQ(one_factor.size(), 1u);
  EXPECT_NEAR(one_factor[0].ratio, 1.0 / 1.02, 0.002);
  EXPECT_NE(one_factor[0].likely_cause.find("read 1.9"), std::string::npos)
      << one_factor[0].likely_cause;
  EXPECT_TRUE(flags("usual", 0.0).empty());
}

// Two recordings of one robot (the figure eight with seeds 1 and 2): each scored whole with the
// other's estimate beats the wrong nominal geometry as the held-out part did above.
TEST(CalibrationValidation, LeaveOneOutScoresEachRecordingWithTheOthersEstimate) {
  const test::ScratchDir scratch("calibration_leave_one_out");
  RecordingsCalibrationParams params;
  for (const int seed : {1, 2}) {
    sim::SimConfig config;
    config.scenario = "worlds/scenarios/figure_eight.yaml";
    config.mode = sim::SimMode::kinematic;
    config.seed = seed;
    const auto dir = scratch / ("seed" + std::to_string(seed));
    writeDataset(dir, sim::simulate(config).dataset);
    params.datasets.push_back(dir.string());
  }
  params.base.methods = {algo::CalibrationMethod::kJoint};
  params.leave_one_out = true;
  const RecordingsCalibration r = calibrateRecordings(params);
  ASSERT_EQ(r.report.leave_one_out.size(), 1u);
  const algo::LeaveOneOutMethod& joint = r.report.leave_one_out[0];
  EXPECT_EQ(joint.method, algo::CalibrationMethod::kJoint);
  ASSERT_EQ(joint.recordings.size(), 2u);
  for (const algo::LeaveOneOutScore& s : joint.recordings) {
    EXPECT_EQ(s.others, 1u);
    ASSERT_TRUE(s.figures) << s.note;
    EXPECT_EQ(s.figures->fraction, 1.0);
    // The whole 26 s drive: raw about 8 deg per 10 s window, as on the held-out part above.
    EXPECT_GT(s.figures->raw.rot_deg, 4.0);
    EXPECT_LT(s.figures->calibrated.rot_deg, 0.25 * s.figures->raw.rot_deg);
    EXPECT_LT(s.figures->calibrated.trans_m, 0.25 * s.figures->raw.trans_m);
  }
  // Each recording's score uses the other's estimate, not its own: the two differ.
  EXPECT_NE(joint.recordings[0].figures->calibrated.trans_m,
            joint.recordings[1].figures->calibrated.trans_m);
}

}  // namespace
}  // namespace slamprep::eval
