// A calibrated lidar mount far from the recording's own (algo/calibration/mount_flag.hpp):
// flagged beyond 5 cm or 5 deg, and the cause says whether the estimate's sigma allows the
// given mount (a loose mount) or excludes it (a wrong tf, or an error absorbed into the mount).
#include "slamprep/algo/calibration/mount_flag.hpp"

#include <gtest/gtest.h>

#include <numbers>

namespace slamprep::algo {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
const SE2 kTf{-0.1, 0.0, 0.0};  // a Neato's base_link -> base_laser_link
const std::string kFrom = "tf base_link -> base_laser_link";

// A joint result with its mount at `mount` and sigmas (x, y, yaw).
CalibrationResult jointResult(const SE2& mount, double sigma_xy_m, double sigma_yaw_rad) {
  CalibrationResult r;
  r.ok = true;
  r.estimates_mount = true;
  r.geometry = {0.035, 0.035, 0.24};
  r.T_base_lidar = mount;
  r.covariance = Eigen::MatrixXd::Identity(6, 6) * 1e-8;
  r.covariance(3, 3) = r.covariance(4, 4) = sigma_xy_m * sigma_xy_m;
  r.covariance(5, 5) = sigma_yaw_rad * sigma_yaw_rad;
  return r;
}

TEST(MountFlag, NoFlagWithinFiveCentimetresAndFiveDegrees) {
  EXPECT_FALSE(mountFlag(jointResult({-0.06, 0.03, 4.9 * kDeg}, 0.001, 0.001), kTf, kFrom));
}

TEST(MountFlag, NoFlagForAMethodThatDoesNotEstimateTheMountOrRefused) {
  CalibrationResult r = jointResult({0.2, 0.0, 0.0}, 0.001, 0.001);
  r.estimates_mount = false;
  EXPECT_FALSE(mountFlag(r, kTf, kFrom));
  r.estimates_mount = true;
  r.ok = false;
  EXPECT_FALSE(mountFlag(r, kTf, kFrom));
}

// The real case: 264 mm beside the tf with a sigma of 7 mm. The fit excludes the tf.
TEST(MountFlag, AConfidentMountFarFromTheTfSaysTheFitExcludesIt) {
  const auto flag = mountFlag(jointResult({-0.1, 0.264, 0.0}, 0.007, 0.012), kTf, kFrom);
  ASSERT_TRUE(flag);
  EXPECT_EQ(flag->param, "lidar_mount");
  EXPECT_NE(flag->likely_cause.find("264 mm and 0.0 deg"), std::string::npos) << flag->likely_cause;
  EXPECT_NE(flag->likely_cause.find(kFrom), std::string::npos);
  EXPECT_NE(flag->likely_cause.find("suspect"), std::string::npos);
}

// 98 mm away with a sigma of 68 mm: the recording leaves the mount loose.
TEST(MountFlag, ALooseMountSaysKeepTheDatasets) {
  const auto flag = mountFlag(jointResult({-0.1, 0.098, 0.0}, 0.068, 0.02), kTf, kFrom);
  ASSERT_TRUE(flag);
  EXPECT_NE(flag->likely_cause.find("does not pin the mount down"), std::string::npos)
      << flag->likely_cause;
  // A yaw within its 5 deg limit is not a verdict, however small its sigma.
  const auto small_yaw =
      mountFlag(jointResult({-0.1, 0.098, 1.4 * kDeg}, 0.068, 0.001 * kDeg), kTf, kFrom);
  ASSERT_TRUE(small_yaw);
  EXPECT_NE(small_yaw->likely_cause.find("does not pin"), std::string::npos);
}

// The yaw wraps: -179 deg against +179 deg is 2 deg apart.
TEST(MountFlag, YawDifferenceWrapsAroundPi) {
  const SE2 backwards{0.0, 0.0, 179.0 * kDeg};
  EXPECT_FALSE(mountFlag(jointResult({0.0, 0.0, -179.0 * kDeg}, 0.001, 0.001), backwards, kFrom));
  EXPECT_TRUE(mountFlag(jointResult({0.0, 0.0, -170.0 * kDeg}, 0.001, 0.001), backwards, kFrom));
}

}  // namespace
}  // namespace slamprep::algo
