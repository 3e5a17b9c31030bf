#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>

#include "slamprep/core/atomic_file.hpp"
#include "slamprep/eval/bench/group_consistency.hpp"
#include "slamprep/eval/bench/summary.hpp"
#include "slamprep/eval/bench/trial_metrics.hpp"
#include "slamprep/eval/bench/trial_record.hpp"
#include "slamprep/eval/bench/trial_timing.hpp"

namespace slamprep::eval {
namespace {

namespace fs = std::filesystem;

const fs::path kTrials = fs::path(SLAMPREP_SOURCE_DIR) / "tests/bench/data/trials";

// to_json then from_json gives the record back, and the JSON twice the same bytes.
template <typename Record>
void expectRoundTrip(const Record& record) {
  const nlohmann::json written = record;
  const Record read = written.get<Record>();
  EXPECT_EQ(read, record) << written.dump(2);
  EXPECT_EQ(nlohmann::json(read).dump(2), written.dump(2));
}

// A trial result file read as a TrialRecord writes back its very bytes (runner.cpp's dump).
void expectSameBytes(const fs::path& file) {
  const std::string text = readFile(file);
  const TrialRecord record = nlohmann::json::parse(text).get<TrialRecord>();
  EXPECT_EQ(nlohmann::json(record).dump(2) + "\n", text) << file;
  expectRoundTrip(record);
}

TEST(Records, CommittedTrialResultsWriteBackTheirBytes) {
  std::size_t files = 0;
  for (const auto& entry : fs::directory_iterator(kTrials))
    if (entry.path().extension() == ".json") expectSameBytes(entry.path()), ++files;
  EXPECT_EQ(files, 4u);
}

TEST(Records, TheFixturesHoldWhatTheyAreFor) {
  const auto read = [](const char* name) {
    return nlohmann::json::parse(readFile(kTrials / name)).get<TrialRecord>();
  };
  const TrialRecord faults = read("faults-random_smooth-all.json");
  EXPECT_FALSE(faults.stamps.empty());
  EXPECT_FALSE(faults.faults.empty());
  ASSERT_TRUE(faults.calibration.contains("joint"));
  EXPECT_TRUE(faults.calibration.at("joint").sideslip.has_value());
  ASSERT_TRUE(faults.matching && faults.matching->loop_closure);
  const TrialRecord jitter = read("faults-arc-stamp_jitter.json");
  EXPECT_TRUE(std::any_of(jitter.deskew.begin(), jitter.deskew.end(),
                          [](const auto& d) { return !d.second.refusals.empty(); }));
  EXPECT_TRUE(jitter.calibration.at("joint").refusal_names_fault.has_value());
}

// Every accessor names a path the summary really has for a record that has the field.
TEST(Records, MetricPathsAreTheFlattenedKeys) {
  const nlohmann::json result =
      nlohmann::json::parse(readFile(kTrials / "faults-random_smooth-all.json"));
  const auto metrics = flattenMetrics(result);
  const TrialRecord record = result.get<TrialRecord>();
  const CalibrationRecord& joint = record.calibration.at("joint");
  EXPECT_EQ(metrics.at(calibrationMetric("joint", CalibrationError::kAbs, CalibrationParam::kB)),
            joint.abs_error[CalibrationParam::kB].value());
  EXPECT_EQ(
      metrics.at(calibrationMetric("joint", CalibrationError::kSigma, CalibrationParam::kMountYaw)),
      joint.sigma[CalibrationParam::kMountYaw].value());
  EXPECT_EQ(metrics.at(calibrationMetric("joint", CalibrationField::kOk)), 1.0);
  EXPECT_EQ(metrics.at(calibrationMetric("joint", CalibrationField::kDrift)),
            joint.drift_m.value());
  EXPECT_EQ(metrics.at(calibrationMetric("joint", OdometryField::kRpeRotRmse)),
            joint.odometry.rpe_rot_rmse_deg.value());
  EXPECT_EQ(metrics.at(deskewMetric("odom-icp", DeskewFigure::kMean)),
            record.deskew.at("odom-icp").figures.mean_m.value());
  EXPECT_EQ(metrics.at(simMetric(SimField::kMeanSpeed)), record.sim.mean_speed_mps);
  EXPECT_EQ(metrics.at(odometryMetric(OdometryGeometry::kTrue, OdometryField::kApeRmse)),
            record.odometry_true.ape_rmse_m.value());
  EXPECT_EQ(metrics.at(matchingMetric(MatchingField::kMaxLinkChange)),
            record.matching->loop_closure->max_link_change_deg);
  EXPECT_EQ(metrics.at(matchingMetric(MatchingField::kConvergedFraction)),
            record.matching->converged_fraction);
  EXPECT_EQ(methodOfMetric(TrialSection::kDeskew, "deskew/odom-icp/mean_m"), "odom-icp");
  EXPECT_EQ(methodOfMetric(TrialSection::kDeskew, "calibration/joint/ok"), "");
  EXPECT_EQ(deskewRefusalMetric("imu", "not-bracketed"),
            "deskew/imu/refused_by_reason/not-bracketed");
  EXPECT_EQ(consistencyMetric("joint", CalibrationParam::kMountX, ConsistencyStat::kCoverage1Sigma),
            "calibration/joint/consistency/lidar_x/coverage_1sigma");
  EXPECT_EQ(consistencyMetric("joint", NeesStat::kMean), "calibration/joint/consistency/nees_mean");
}

CalibrationRecord estimate() {
  CalibrationRecord r;
  r.ok = true;
  r.condition_number = 12.5;
  for (const CalibrationParam p : kCalibrationParams) {
    r.abs_error[p] = 0.25;
    r.signed_error[p] = -0.25;
  }
  r.sigma[CalibrationParam::kB] = 0.125;
  r.nees = 3.5;
  r.inside_3sigma = true;
  r.drift_m = 0.03;
  r.odometry = {
      .ape_rmse_m = 0.1, .ape_max_m = 0.2, .rpe_trans_rmse_m = 0.01, .rpe_rot_rmse_deg = 0.5};
  r.sideslip = SideslipRecord{1.5, 0.25};
  return r;
}

TEST(Records, CalibrationRoundTrips) {
  expectRoundTrip(estimate());
  CalibrationRecord refused;
  refused.reason = "too few intervals (encoder spikes)";
  refused.refusal_names_fault = true;
  expectRoundTrip(refused);
  const nlohmann::json j = refused;
  EXPECT_FALSE(j.contains("abs_error"));  // an empty parameter object is not written
  EXPECT_FALSE(j.contains("condition_number"));
  EXPECT_EQ(nlohmann::json(estimate())["sigma"].size(), 1u);
}

// A non-finite number is written as null and read back as NaN, so it is written as null again.
TEST(Records, ANullNumberWritesBackAsNull) {
  CalibrationRecord r = estimate();
  r.condition_number = std::numeric_limits<double>::infinity();
  const std::string text = nlohmann::json(r).dump();
  const CalibrationRecord read = nlohmann::json::parse(text).get<CalibrationRecord>();
  EXPECT_TRUE(std::isnan(read.condition_number.value()));
  EXPECT_EQ(nlohmann::json(read).dump(), text);
  DeskewRecord d;
  d.figures.mean_m = std::nan("");
  const std::string deskew = nlohmann::json(d).dump();
  EXPECT_NE(deskew.find("\"mean_m\":null"), std::string::npos) << deskew;
  EXPECT_EQ(nlohmann::json(nlohmann::json::parse(deskew).get<DeskewRecord>()).dump(), deskew);
}

TEST(Records, SimMatchingAndOdometryRoundTrip) {
  expectRoundTrip(SimRecord{.duration_s = 58.25,
                            .scans = 582,
                            .beams = 209520,
                            .distance_m = 18.9,
                            .turned_rad = 39.0,
                            .mean_abs_yaw_rate_radps = 0.67,
                            .mean_speed_mps = 0.32,
                            .drift_nominal_m = 0.578,
                            .drift_true_m = 3.4e-4});
  expectRoundTrip(OdometryRecord{});
  OdometryRecord ape_only;
  ape_only.ape_rmse_m = 0.5;
  ape_only.ape_max_m = 1.5;
  expectRoundTrip(ape_only);
  MatchingRecord m;
  m.pairs = 581;
  m.converged_fraction = 0.995;
  expectRoundTrip(m);
  m.error = MatchErrorRecord{1.2e-3, 1.5e-3, 0.0127, 0.02};
  m.loop_closure = LoopClosureRecord{3, 5, 0.125};
  expectRoundTrip(m);
  EXPECT_EQ(nlohmann::json(m)["trans_error_m_rmse"], 1.5e-3);  // beside pairs, not nested
}

TEST(Records, DeskewRoundTrips) {
  DeskewRecord d;
  d.ok = true;
  d.figures.mean_m = 1e-3;
  d.figures.rms_m = 2e-3;
  d.figures.max_m = 4e-3;
  d.figures.beams = 36000;
  expectRoundTrip(d);
  d.ok = false;
  d.refused_scans = 2;
  d.refused_by_reason = {{"not-bracketed", 1}, {"sample-gap", 1}};
  d.refusals = {{3, "odom-linear", "not-bracketed", "scan 3: ..."},
                {7, "odom-linear", "sample-gap", "scan 7: ..."}};
  expectRoundTrip(d);
  EXPECT_EQ(nlohmann::json(d)["refusals"][1]["scan"], 7);
}

TEST(Records, ArtifactsStampsAndTimingRoundTrip) {
  ArtifactsRecord a;
  a.trajectory.truth = {{0, 0}, {1, 0.5}};
  a.trajectory.nominal = {{0, 0}, {1.1, 0.4}};
  a.odometry_error.nominal = {.t = {0, 0.1}, .translation_m = {0, 0.01}, .heading_deg = {0, -1}};
  expectRoundTrip(a);
  a.trajectory.calibrated = WorldPoints{{0, 0}, {1.01, 0.49}};
  a.trajectory.calibrated_method = "joint";
  a.odometry_error.calibrated = a.odometry_error.nominal;
  a.scan = ArtifactScanRecord{.index = 4,
                              .stamp_s = 0.4,
                              .lidar = {1, 2, 0.5},
                              .raw = {{1, 1}},
                              .truth = {{1.01, 1}},
                              .deskewed = WorldPoints{{1.009, 1}},
                              .deskew_method = "imu"};
  expectRoundTrip(a);
  expectRoundTrip(StampsRecord{{"scans", {true, "", 200, 0.1, 1e-3, 3e-3, 0}},
                               {"imu", {false, "regular already", 4000, 0.005, 0, 0, 0}}});
  TrialTiming t;
  t.simulate_s = 0.4;
  expectRoundTrip(t);
  t.motion_s = 0.6;
  t.calibration = {{"joint", 0.007}};
  t.deskew = {{"imu", 0.02}};
  expectRoundTrip(t);
}

TEST(Records, ATrialRoundTrips) {
  TrialRecord r;
  r.sim.scans = 10;
  r.odometry_nominal.ape_rmse_m = 0.9;
  r.calibration["joint"] = estimate();
  r.deskew["none"].ok = true;
  r.faults = {{"glass", 1}};
  r.trial = {{"id", "0000-room-default-s1"}};
  expectRoundTrip(r);
  const nlohmann::json j = r;
  EXPECT_FALSE(j.contains("stamps"));  // empty sections are not written
  EXPECT_FALSE(j.contains("matching"));
  EXPECT_EQ(calibrationRecords(j).at("joint"), estimate());
}

}  // namespace
}  // namespace slamprep::eval
