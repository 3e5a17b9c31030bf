#include "slamprep/algo/calibration/interval.hpp"

#include <gtest/gtest.h>

#include <numbers>
#include <sstream>

#include "slamprep/core/error.hpp"
#include "synthetic.hpp"

namespace slamprep::algo {
namespace {

TEST(CalibrationInterval, MeanRatesAreSumsOverDuration) {
  CalibrationInterval interval{1.0, 1.5, {{0.2, 0.4, 0.6}, {0.3, 0.9, -0.3}}, {}};
  EXPECT_DOUBLE_EQ(interval.sumLeft_rad(), 1.3);
  EXPECT_DOUBLE_EQ(interval.sumRight_rad(), 0.3);
  EXPECT_DOUBLE_EQ(interval.meanRateLeft_radps(), 1.3 / 0.5);
  EXPECT_DOUBLE_EQ(interval.meanRateRight_radps(), 0.3 / 0.5);
}

TEST(IntervalRecords, RoundTripIsExactForSingleStepIntervals) {
  std::vector<CalibrationInterval> in;
  double t = 0.0;
  for (int k = 0; k < 20; ++k) {
    const double T = 0.1 + 0.013 * k;
    in.push_back({t, t + T, {{T, 0.3 * k - 1.0, 0.7 - 0.01 * k * k}}, {0.1 * k, -0.02 * k, 0.05}});
    t += T;
  }
  std::stringstream ss;
  writeIntervalRecords(ss, in);
  const auto out = readIntervalRecords(ss, "mem");
  ASSERT_EQ(out.size(), in.size());
  for (std::size_t k = 0; k < in.size(); ++k) {
    // T, phi and sm are written with round-trip precision; dphi = phi * T is then one rounding
    // of (dphi / T) * T away from the original: a few ulp.
    EXPECT_DOUBLE_EQ(out[k].duration_s(), in[k].duration_s());
    EXPECT_DOUBLE_EQ(out[k].meanRateLeft_radps(), in[k].meanRateLeft_radps());
    EXPECT_DOUBLE_EQ(out[k].meanRateRight_radps(), in[k].meanRateRight_radps());
    EXPECT_NEAR(out[k].steps[0].dphi_left_rad, in[k].steps[0].dphi_left_rad, 1e-15);
    EXPECT_EQ(out[k].T_lidarStart_lidarEnd.x, in[k].T_lidarStart_lidarEnd.x);
    EXPECT_EQ(out[k].T_lidarStart_lidarEnd.y, in[k].T_lidarStart_lidarEnd.y);
    EXPECT_EQ(out[k].T_lidarStart_lidarEnd.yaw, in[k].T_lidarStart_lidarEnd.yaw);
  }
  // Written again, the bytes are identical.
  std::stringstream again;
  writeIntervalRecords(again, out);
  EXPECT_EQ(again.str(), ss.str());
}

TEST(IntervalRecords, ReadsCensiLinesIgnoringExtraKeysAndBlankLines) {
  std::stringstream ss(
      "{\"T\": 0.5, \"phi_l\": 2.0, \"phi_r\": 4.0, \"sm\": [0.1, 0.0, 0.2], \"extra\": 1}\n"
      "\n"
      "{\"T\": 1, \"phi_l\": -1, \"phi_r\": 1, \"sm\": [0, 0, 0.5]}\n");
  const auto out = readIntervalRecords(ss, "mem");
  ASSERT_EQ(out.size(), 2u);
  EXPECT_DOUBLE_EQ(out[0].sumLeft_rad(), 1.0);
  EXPECT_DOUBLE_EQ(out[0].sumRight_rad(), 2.0);
  EXPECT_DOUBLE_EQ(out[1].t_start_s, 0.5);
  EXPECT_DOUBLE_EQ(out[1].t_end_s, 1.5);
}

// Censi's published lstraight.tuple holds two records one after another on its line 1082.
TEST(IntervalRecords, ReadsSeveralObjectsOnOneLine) {
  std::stringstream ss;
  ss << "{\"T\": 0.5, \"phi_l\": 2, \"phi_r\": 4, \"sm\": [0.1, 0, 0.2]}\n"
     << "{\"T\": 1, \"phi_l\": 1, \"phi_r\": 1, \"sm\": [0.2, 0, 0]}"
     << "{\"T\": 0.25, \"phi_l\": 4, \"phi_r\": 0, \"sm\": [0, 0, -0.1]} \n"
     << "{\"T\": 2, \"phi_l\": 1, \"phi_r\": 2, \"sm\": [0.3, 0, 0.1]}\n";
  const auto out = readIntervalRecords(ss, "lstraight.tuple");
  ASSERT_EQ(out.size(), 4u);
  EXPECT_DOUBLE_EQ(out[1].t_start_s, 0.5);
  EXPECT_DOUBLE_EQ(out[2].t_start_s, 1.5);
  EXPECT_DOUBLE_EQ(out[2].sumLeft_rad(), 1.0);
  EXPECT_DOUBLE_EQ(out[2].T_lidarStart_lidarEnd.yaw, -0.1);
  EXPECT_DOUBLE_EQ(out[3].t_end_s, 3.75);
  // A bad second record on a line is named by its line and place.
  std::stringstream bad("{\"T\": 1, \"phi_l\": 1, \"phi_r\": 1, \"sm\": [0, 0, 0]}{\"T\": -1}\n");
  try {
    readIntervalRecords(bad, "t.tuple");
    ADD_FAILURE() << "accepted a negative T";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("t.tuple:1 record 2"), std::string::npos) << e.what();
  }
}

TEST(IntervalRecords, MalformedRecordNamesItsLine) {
  const std::string good = "{\"T\": 0.5, \"phi_l\": 2, \"phi_r\": 4, \"sm\": [0.1, 0, 0.2]}\n";
  const std::vector<std::pair<std::string, std::string>> bad = {
      {"not json", "not JSON"},
      {"[1, 2, 3]", "JSON object"},
      {"{\"phi_l\": 2, \"phi_r\": 4, \"sm\": [0, 0, 0]}", "\"T\""},
      {"{\"T\": -1, \"phi_l\": 2, \"phi_r\": 4, \"sm\": [0, 0, 0]}", "positive"},
      {"{\"T\": 1, \"phi_l\": \"2\", \"phi_r\": 4, \"sm\": [0, 0, 0]}", "phi_l"},
      {"{\"T\": 1, \"phi_l\": 2, \"sm\": [0, 0, 0]}", "phi_r"},
      {"{\"T\": 1, \"phi_l\": 2, \"phi_r\": 4, \"sm\": [0, 0]}", "sm"},
      {"{\"T\": 1, \"phi_l\": 2, \"phi_r\": 4, \"sm\": [0, null, 0]}", "sm"},
  };
  for (const auto& [line, what] : bad) {
    std::stringstream ss(good + "\n" + line + "\n" + good);
    try {
      readIntervalRecords(ss, "tuples.jsonl");
      ADD_FAILURE() << "accepted: " << line;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("tuples.jsonl:3"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  }
}

// Encoders at 100 Hz, wheels turning at 2 and 3 rad/s from t = 1 s (standing still before);
// lidar poses at 10 Hz from a straight drive.
struct LogFixture {
  EncoderLog encoders;
  PoseSeries T_world_lidar;
  int tpr = 4096;
  LogFixture() {
    const double rad_per_tick = 2.0 * std::numbers::pi / tpr;
    for (int i = 0; i <= 300; ++i) {
      const double t = 0.01 * i, moving = std::max(0.0, t - 1.0);
      encoders.push_back({t, std::llround(2.0 * moving / rad_per_tick),
                          std::llround(3.0 * moving / rad_per_tick)});
    }
    for (int i = 0; i <= 29; ++i) {
      const double t = 0.005 + 0.1 * i;
      T_world_lidar.push_back(t, SE2(0.25 * std::max(0.0, t - 1.0), 0.0, 0.0));
    }
  }
};

TEST(BuildIntervals, ConsecutivePosesDropStandstillAndCutStepsAtTheEnds) {
  LogFixture f;
  const IntervalSet set = buildIntervals(f.encoders, f.tpr, f.T_world_lidar);
  // 29 gaps between 30 poses; the wheels start at t = 1 s, so the 9 gaps ending at or before
  // t = 0.905 s are standing still and the gap [0.905, 1.005] already turns 0.01 rad.
  EXPECT_EQ(set.dropped_uncovered, 0);
  EXPECT_EQ(set.dropped_standstill, 9);
  ASSERT_EQ(set.intervals.size(), 20u);
  const double rad_per_tick = 2.0 * std::numbers::pi / f.tpr;
  for (const CalibrationInterval& in : set.intervals) {
    double dt = 0.0;
    for (const EncoderStep& s : in.steps) dt += s.dt_s;
    EXPECT_NEAR(dt, in.duration_s(), 1e-12);
    // Wheel angle = 2 (t - 1) rad after t = 1 s, quantised to one tick at the samples.
    const double expected =
        2.0 * (std::max(0.0, in.t_end_s - 1.0) - std::max(0.0, in.t_start_s - 1.0));
    EXPECT_NEAR(in.sumLeft_rad(), expected, 2 * rad_per_tick);
  }
}

TEST(BuildIntervals, KeyframesEveryTenCentimetres) {
  LogFixture f;
  IntervalParams params;
  params.keyframe_translation_m = 0.099;  // just under 0.4 s of driving, robust to rounding
  const IntervalSet set = buildIntervals(f.encoders, f.tpr, f.T_world_lidar, params);
  ASSERT_FALSE(set.intervals.empty());
  for (const CalibrationInterval& in : set.intervals)
    EXPECT_GE(in.T_lidarStart_lidarEnd.translation().norm(), 0.099);
  // 0.25 m/s, 10 cm per keyframe: every 0.4 s, i.e. 4 scans.
  EXPECT_NEAR(set.intervals[1].duration_s(), 0.4, 1e-9);
}

TEST(BuildIntervals, UncoveredIntervalsAreCounted) {
  LogFixture f;
  PoseSeries late;
  late.push_back(2.9, SE2());
  late.push_back(3.2, SE2(0.1, 0, 0));
  const IntervalSet set = buildIntervals(f.encoders, f.tpr, late);
  EXPECT_TRUE(set.intervals.empty());
  EXPECT_EQ(set.dropped_uncovered, 1);
}

TEST(MotionModel, IntegrationMatchesCoreOdometry) {
  testing::SyntheticSpec spec;
  spec.T_base_lidar = SE2();
  const auto intervals = testing::makeIntervals(spec);
  for (const auto& in : intervals) {
    const SE2 o = integrateInterval(in, spec.truth);
    EXPECT_NEAR(o.x, in.T_lidarStart_lidarEnd.x, 1e-13);
    EXPECT_NEAR(o.y, in.T_lidarStart_lidarEnd.y, 1e-13);
    EXPECT_NEAR(o.yaw, in.T_lidarStart_lidarEnd.yaw, 1e-13);
    // With zero offset the shifted integration is the plain one.
    const auto shifted =
        integrateStepsShifted(in.steps, spec.truth.radius_left_m, spec.truth.radius_right_m,
                              spec.truth.wheel_base_m, 0.0);
    EXPECT_NEAR(shifted.x, o.x, 1e-13);
    EXPECT_NEAR(shifted.yaw, o.yaw, 1e-13);
  }
}

// The lidar motion of an off-centre, backwards lidar moved to the base frame through its mount is
// the base motion the true geometry integrates (forward), and back through the inverse (inverse).
TEST(InBaseFrame, ALidarMotionThroughItsMountIsTheBaseMotion) {
  testing::SyntheticSpec spec;
  spec.T_base_lidar = SE2(-0.2, 0.05, 3.0);
  const auto lidar = testing::makeIntervals(spec);
  const auto base = inBaseFrame(lidar, spec.T_base_lidar);
  const auto back = inBaseFrame(base, spec.T_base_lidar.inverse());
  ASSERT_EQ(base.size(), lidar.size());
  for (std::size_t k = 0; k < base.size(); ++k) {
    const SE2 truth = integrateInterval(lidar[k], spec.truth);
    EXPECT_NEAR(base[k].T_lidarStart_lidarEnd.x, truth.x, 1e-12);
    EXPECT_NEAR(base[k].T_lidarStart_lidarEnd.y, truth.y, 1e-12);
    EXPECT_NEAR(base[k].T_lidarStart_lidarEnd.yaw, truth.yaw, 1e-12);
    EXPECT_NEAR(back[k].T_lidarStart_lidarEnd.x, lidar[k].T_lidarStart_lidarEnd.x, 1e-12);
    EXPECT_NEAR(back[k].T_lidarStart_lidarEnd.y, lidar[k].T_lidarStart_lidarEnd.y, 1e-12);
    EXPECT_EQ(base[k].steps.size(), lidar[k].steps.size());  // the wheels untouched
  }
}

}  // namespace
}  // namespace slamprep::algo
