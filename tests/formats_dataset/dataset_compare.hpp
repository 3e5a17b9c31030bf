#pragma once
// Bit-for-bit comparison of datasets for the round-trip tests.

#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <string>

#include "slamprep/core/dataset.hpp"

namespace slamprep::synthetic {

inline ::testing::AssertionResult sameBits(double a, double b) {
  if (std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b))
    return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << a << " vs " << b << " differ in their bits";
}

inline ::testing::AssertionResult samePose(const SE2& a, const SE2& b) {
  for (int i = 0; i < 3; ++i)
    if (auto r = sameBits(a.vector()[i], b.vector()[i]); !r)
      return r << " (pose component " << i << ")";
  return ::testing::AssertionSuccess();
}

inline void expectSamePoses(const PoseSeries& a, const PoseSeries& b, const std::string& what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  for (std::size_t k = 0; k < a.size(); ++k) {
    ASSERT_TRUE(sameBits(a[k].stamp_s, b[k].stamp_s)) << what << "[" << k << "]";
    ASSERT_TRUE(samePose(a[k].value, b[k].value)) << what << "[" << k << "]";
  }
}

inline void expectSameScan(const ScanRecord& a, const ScanRecord& b, std::size_t k) {
  const LaserScan &sa = a.scan, &sb = b.scan;
  for (auto [x, y] : {std::pair{sa.stamp_s, sb.stamp_s},
                      {sa.angle_min_rad, sb.angle_min_rad},
                      {sa.angle_increment_rad, sb.angle_increment_rad},
                      {sa.time_increment_s, sb.time_increment_s},
                      {sa.scan_time_s, sb.scan_time_s},
                      {sa.range_min_m, sb.range_min_m},
                      {sa.range_max_m, sb.range_max_m}})
    ASSERT_TRUE(sameBits(x, y)) << "scan " << k;
  ASSERT_EQ(sa.size(), sb.size()) << "scan " << k;
  for (std::size_t i = 0; i < sa.size(); ++i)
    ASSERT_TRUE(sameBits(sa.ranges_m[i], sb.ranges_m[i])) << "scan " << k << " beam " << i;
  ASSERT_EQ(a.T_world_base_true.has_value(), b.T_world_base_true.has_value()) << "scan " << k;
  if (a.T_world_base_true) {
    ASSERT_TRUE(samePose(*a.T_world_base_true, *b.T_world_base_true)) << "scan " << k;
  }
  ASSERT_EQ(a.T_odom_base_nominal.has_value(), b.T_odom_base_nominal.has_value());
  if (a.T_odom_base_nominal) {
    ASSERT_TRUE(samePose(*a.T_odom_base_nominal, *b.T_odom_base_nominal)) << "scan " << k;
  }
  ASSERT_EQ(a.p_ref_true.size(), b.p_ref_true.size()) << "scan " << k;
  for (std::size_t i = 0; i < a.p_ref_true.size(); ++i) {
    ASSERT_EQ(a.p_ref_true[i].has_value(), b.p_ref_true[i].has_value()) << "beam " << i;
    if (!a.p_ref_true[i]) continue;
    ASSERT_TRUE(sameBits(a.p_ref_true[i]->x(), b.p_ref_true[i]->x())) << "beam " << i;
    ASSERT_TRUE(sameBits(a.p_ref_true[i]->y(), b.p_ref_true[i]->y())) << "beam " << i;
  }
}

inline void expectSameDataset(const Dataset& a, const Dataset& b) {
  const DatasetInfo &ia = a.info, &ib = b.info;
  EXPECT_EQ(ia.format_version, ib.format_version);
  EXPECT_EQ(ia.world, ib.world);
  EXPECT_EQ(ia.scenario, ib.scenario);
  EXPECT_EQ(ia.seed, ib.seed);
  ASSERT_EQ(ia.true_geometry.has_value(), ib.true_geometry.has_value());
  auto sameGeometry = [](const DiffDriveParams& x, const DiffDriveParams& y) {
    EXPECT_TRUE(sameBits(x.radius_left_m, y.radius_left_m));
    EXPECT_TRUE(sameBits(x.radius_right_m, y.radius_right_m));
    EXPECT_TRUE(sameBits(x.wheel_base_m, y.wheel_base_m));
  };
  if (ia.true_geometry) sameGeometry(*ia.true_geometry, *ib.true_geometry);
  sameGeometry(ia.nominal_geometry, ib.nominal_geometry);
  EXPECT_TRUE(samePose(ia.T_base_lidar, ib.T_base_lidar));
  EXPECT_EQ(ia.ticks_per_revolution, ib.ticks_per_revolution);
  EXPECT_EQ(ia.config, ib.config);
  expectSamePoses(a.groundtruth, b.groundtruth, "groundtruth");
  expectSamePoses(a.odom_nominal, b.odom_nominal, "odom_nominal");
  expectSamePoses(a.odometry_logged, b.odometry_logged, "odometry_logged");
  ASSERT_EQ(a.encoders.size(), b.encoders.size());
  for (std::size_t k = 0; k < a.encoders.size(); ++k) {
    ASSERT_TRUE(sameBits(a.encoders[k].stamp_s, b.encoders[k].stamp_s)) << "encoder " << k;
    ASSERT_EQ(a.encoders[k].ticks_left, b.encoders[k].ticks_left) << "encoder " << k;
    ASSERT_EQ(a.encoders[k].ticks_right, b.encoders[k].ticks_right) << "encoder " << k;
  }
  ASSERT_EQ(a.imu.size(), b.imu.size());
  for (std::size_t k = 0; k < a.imu.size(); ++k) {
    const ImuSample &x = a.imu[k], &y = b.imu[k];
    ASSERT_TRUE(sameBits(x.stamp_s, y.stamp_s) && sameBits(x.gyro_z_radps, y.gyro_z_radps) &&
                sameBits(x.accel_x_mps2, y.accel_x_mps2) &&
                sameBits(x.accel_y_mps2, y.accel_y_mps2))
        << "imu " << k;
  }
  ASSERT_EQ(a.scans.size(), b.scans.size());
  for (std::size_t k = 0; k < a.scans.size(); ++k) expectSameScan(a.scans[k], b.scans[k], k);
}

}  // namespace slamprep::synthetic
