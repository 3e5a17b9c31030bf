#include "slamprep/eval/metrics/calibration_error.hpp"

#include <gtest/gtest.h>

#include <numbers>

namespace slamprep::eval {
namespace {

using std::numbers::pi;

TEST(CalibrationError, RelativeGeometryAndMillimetreDegreeMount) {
  CalibrationEstimate est;
  est.geometry = {0.101, 0.0995, 0.49};
  est.T_base_lidar = SE2(0.102, -0.003, 0.05);
  const DiffDriveParams truth{0.1, 0.1, 0.5};
  const CalibrationErrorResult r = calibrationError(est, truth, SE2(0.1, 0.0, 0.04));
  ASSERT_TRUE(r.ok) << r.reason;
  ASSERT_EQ(r.parameters.size(), 6u);
  EXPECT_EQ(r.parameters[0].name, "r_L");
  EXPECT_NEAR(r.parameters[0].error, 0.01, 1e-12);    // (0.101 - 0.1) / 0.1
  EXPECT_NEAR(r.parameters[1].error, -0.005, 1e-12);  // (0.0995 - 0.1) / 0.1
  EXPECT_NEAR(r.parameters[2].error, -0.02, 1e-12);   // (0.49 - 0.5) / 0.5
  EXPECT_EQ(r.parameters[3].unit, "mm");
  EXPECT_NEAR(r.parameters[3].error, 2.0, 1e-9);   // 2 mm
  EXPECT_NEAR(r.parameters[4].error, -3.0, 1e-9);  // -3 mm
  EXPECT_EQ(r.parameters[5].unit, "deg");
  EXPECT_NEAR(r.parameters[5].error, 0.01 * 180 / pi, 1e-9);
  EXPECT_FALSE(r.all_within_3_sigma.has_value());
  EXPECT_FALSE(r.parameters[0].within_3_sigma.has_value());
}

TEST(CalibrationError, ThreeSigmaTest) {
  CalibrationEstimate est;
  est.geometry = {0.1003, 0.1, 0.5};
  const DiffDriveParams truth{0.1, 0.1, 0.5};
  // r_L off by 0.3 mm: sigma 0.1 mm puts it exactly on the 3-sigma boundary (inside: <=).
  est.geometry_sigma = Eigen::Vector3d(0.10001e-3, 1e-4, 1e-4);
  CalibrationErrorResult r = calibrationError(est, truth);
  ASSERT_TRUE(r.ok);
  EXPECT_NEAR(*r.parameters[0].sigma, 0.10001e-3 / 0.1, 1e-15);  // relative, like the error
  EXPECT_TRUE(*r.parameters[0].within_3_sigma);
  EXPECT_TRUE(*r.all_within_3_sigma);
  est.geometry_sigma = Eigen::Vector3d(0.09e-3, 1e-4, 1e-4);  // 3 sigma = 0.27 mm < 0.3 mm
  r = calibrationError(est, truth);
  EXPECT_FALSE(*r.parameters[0].within_3_sigma);
  EXPECT_TRUE(*r.parameters[1].within_3_sigma);
  EXPECT_FALSE(*r.all_within_3_sigma);
}

TEST(CalibrationError, MountYawErrorWrapsAroundPi) {
  CalibrationEstimate est;
  est.T_base_lidar = SE2(0, 0, pi - 0.01);
  est.mount_sigma = Eigen::Vector3d(1e-3, 1e-3, 0.01);
  const CalibrationErrorResult r = calibrationError(est, {}, SE2(0, 0, -pi + 0.01));
  ASSERT_TRUE(r.ok);
  EXPECT_NEAR(r.parameters[5].error, -0.02 * 180 / pi, 1e-9);  // not 358 degrees
  EXPECT_NEAR(*r.parameters[5].sigma, 0.01 * 180 / pi, 1e-12);
  EXPECT_TRUE(*r.parameters[5].within_3_sigma);
}

TEST(CalibrationError, MountComparedOnlyWhenBothSidesHaveOne) {
  CalibrationEstimate est;
  est.T_base_lidar = SE2(0.1, 0, 0);
  EXPECT_EQ(calibrationError(est, {}).parameters.size(), 3u);
}

TEST(CalibrationError, RefusesInvalidInputs) {
  CalibrationEstimate est;
  EXPECT_FALSE(calibrationError(est, {0.0, 0.1, 0.5}).ok);
  EXPECT_FALSE(calibrationError(est, {0.1, 0.1, -0.5}).ok);
  est.geometry.wheel_base_m = std::nan("");
  EXPECT_FALSE(calibrationError(est, {}).ok);
  est = {};
  est.geometry_sigma = Eigen::Vector3d(-1, 0, 0);
  EXPECT_FALSE(calibrationError(est, {}).ok);
}

}  // namespace
}  // namespace slamprep::eval
