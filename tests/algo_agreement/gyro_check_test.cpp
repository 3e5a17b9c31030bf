// The gyro's check of a calibrated wheel base (algo/calibration/gyro_check.hpp): with the gyro
// fit's a = r_R / b and c = r_L / b, b_gyro = (r_L + r_R) / (a + c).
#include "slamprep/algo/calibration/gyro_check.hpp"

#include <gtest/gtest.h>

namespace slamprep::algo {
namespace {

SensorAgreement gyroSays(double r_L, double r_R, double b) {
  SensorAgreement a;
  PairAgreement p;
  p.a = "wheels";
  p.b = "gyro";
  p.wheel_ratios = Eigen::Vector2d(r_R / b, r_L / b);
  a.pairs.push_back(p);
  return a;
}

CalibrationResult result(double b, double sigma_b) {
  CalibrationResult r;
  r.ok = true;
  r.geometry = {0.1, 0.1, b};
  r.covariance = Eigen::Matrix3d::Identity() * 1e-12;
  r.covariance(2, 2) = sigma_b * sigma_b;
  return r;
}

TEST(GyroCheck, TheGyrosWheelBaseUsesTheResultsRadii) {
  const SensorAgreement gyro = gyroSays(0.1, 0.1, 0.5);
  EXPECT_NEAR(*gyroWheelBase(result(0.5, 0.001), gyro), 0.5, 1e-12);
  CalibrationResult bigger = result(0.5, 0.001);
  bigger.geometry.radius_left_m = bigger.geometry.radius_right_m = 0.11;
  EXPECT_NEAR(*gyroWheelBase(bigger, gyro), 0.55, 1e-12);
}

TEST(GyroCheck, FlagsAWheelBaseTheGyroDoesNotSupport) {
  const SensorAgreement gyro = gyroSays(0.1, 0.1, 0.5);
  EXPECT_FALSE(gyroFlag(result(0.51, 0.001), gyro));  // 2 %: under the 3 % floor
  const auto flag = gyroFlag(result(0.55, 0.001), gyro);
  ASSERT_TRUE(flag);
  EXPECT_EQ(flag->param, "b_vs_gyro");
  EXPECT_NEAR(flag->ratio, 1.1, 1e-12);
  EXPECT_NE(flag->likely_cause.find("500.0 mm"), std::string::npos) << flag->likely_cause;
  EXPECT_FALSE(gyroFlag(result(0.55, 0.02), gyro));  // within 3 sigma of its own uncertainty
  EXPECT_FALSE(gyroFlag(result(0.55, 0.001), SensorAgreement{}));  // no gyro: nothing to say
}

TEST(GyroCheck, FlagsAWheelBaseFromWheelsThatFollowTheGyro) {
  SensorAgreement derived = gyroSays(0.1, 0.1, 0.5);
  EXPECT_FALSE(gyroHeadedWheelsFlag(result(0.5, 0.001), derived));
  derived.wheels_follow_gyro = true;
  const auto flag = gyroHeadedWheelsFlag(result(0.5, 0.001), derived);
  ASSERT_TRUE(flag);
  EXPECT_EQ(flag->param, "b_not_measured");
  EXPECT_NE(flag->likely_cause.find("/joint_states"), std::string::npos) << flag->likely_cause;
  CalibrationResult refused = result(0.5, 0.001);
  refused.ok = false;
  EXPECT_FALSE(gyroHeadedWheelsFlag(refused, derived));  // a refusal has nothing to flag
}

// No gyro: the wheels against the scans is what can show a lifted robot, and a result is flagged
// with the spans (with a gyro, calibrate refuses on the wheels against it instead).
TEST(GyroCheck, WithoutAGyroTheWheelsAgainstTheScansAreFlagged) {
  SensorAgreement scans;
  scans.sources.push_back({"wheels", 100.0, 160.0, 0.0, 0.0});
  PairAgreement p;
  p.a = "wheels";
  p.b = "scans";
  p.disagreements.push_back({130.0, 141.0, 0.7, 0.3, 0.2, "the robot was lifted or blocked"});
  scans.pairs.push_back(p);
  const auto flag = wheelsScansFlag(result(0.5, 0.001), scans);
  ASSERT_TRUE(flag);
  EXPECT_EQ(flag->param, "wheels_vs_scans");
  EXPECT_NE(flag->likely_cause.find("+30.0..+41.0 s from the start (the robot was lifted"),
            std::string::npos)
      << flag->likely_cause;
  scans.pairs[0].disagreements.clear();
  EXPECT_FALSE(wheelsScansFlag(result(0.5, 0.001), scans));  // they agree
  SensorAgreement with_gyro = gyroSays(0.1, 0.1, 0.5);
  with_gyro.pairs.push_back(p);
  EXPECT_FALSE(wheelsScansFlag(result(0.5, 0.001), with_gyro));
}

}  // namespace
}  // namespace slamprep::algo
