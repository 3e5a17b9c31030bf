// The lidar mount of an imported bag from its whole tf tree (/tf_static and /tf composed over any
// number of hops), an upside-down lidar read as a mirrored scan, a tilted one refused.
#include <gtest/gtest.h>

#include <numbers>

#include "bag_writer.hpp"
#include "slamprep/core/error.hpp"
#include "slamprep/eval/formats/import.hpp"

namespace slamprep::eval {
namespace {
using test::pose3;
using test::transform;

ImportParams withGeometry() {
  ImportParams p;
  p.nominal_geometry = DiffDriveParams{0.1, 0.1, 0.5};
  return p;
}

std::string errorOf(const std::string& bag, const ImportParams& p) {
  try {
    importMcap(bag, "tf.mcap", p);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(ImportTf, ComposesAThreeHopTreeOfStaticAndDynamicTransforms) {
  // base_link -> chassis (static, rolled +0.2 rad) -> mast (on /tf, rolled back -0.2 rad) ->
  // laser (static, yaw 0.4): the hops are tilted, their product is level.
  const Eigen::Isometry3d T_base_chassis = pose3(0.1, 0.0, 0.2, 0.2, 0.0, 0.0);
  const Eigen::Isometry3d T_chassis_mast = pose3(0.0, 0.03, 0.1, -0.2, 0.0, 0.0);
  const Eigen::Isometry3d T_mast_laser = pose3(0.05, 0.02, 0.3, 0.0, 0.0, 0.4);
  test::RobotBagParams b;
  b.tf_static = {transform("base_link", "chassis", T_base_chassis),
                 transform("mast", "laser", T_mast_laser)};
  b.tf = {transform("chassis", "mast", T_chassis_mast)};
  const ImportResult r = importMcap(test::robotBag(b), "tf.mcap", withGeometry());
  const Eigen::Isometry3d T = T_base_chassis * T_chassis_mast * T_mast_laser;
  const SE2& m = r.dataset.info.T_base_lidar;
  EXPECT_NEAR(m.x, T.translation().x(), 1e-12);
  EXPECT_NEAR(m.y, T.translation().y(), 1e-12);
  EXPECT_NEAR(m.yaw, 0.4, 1e-12);
  EXPECT_EQ(r.dataset.info.config["lidar_mount_from"], "tf base_link -> chassis -> mast -> laser");
  // A wrong order of composition (or dropping the middle hop) would move the lidar by
  // centimetres: the translation above is checked to 1e-12 m, so it is the full product.
  EXPECT_GT((T.translation() - (T_base_chassis * T_mast_laser).translation()).norm(), 0.03);
}

TEST(ImportTf, GoesUpToTheCommonAncestorWhenTheLaserHangsFromAnotherBranch) {
  // --base-frame chassis, with base_link -> chassis (0.1 m up, yaw 0.1) and base_link -> laser:
  // chassis -> laser = T_base_chassis^-1 T_base_laser.
  const Eigen::Isometry3d T_bc = pose3(0.0, 0.0, 0.1, 0.0, 0.0, 0.1);
  const Eigen::Isometry3d T_bl = pose3(0.3, 0.1, 0.4, 0.0, 0.0, -0.2);
  test::RobotBagParams b;
  b.tf_static = {transform("base_link", "chassis", T_bc), transform("base_link", "laser", T_bl)};
  ImportParams p = withGeometry();
  p.base_frame = "chassis";
  const ImportResult r = importMcap(test::robotBag(b), "tf.mcap", p);
  const Eigen::Isometry3d T = T_bc.inverse() * T_bl;
  EXPECT_NEAR(r.dataset.info.T_base_lidar.x, T.translation().x(), 1e-12);
  EXPECT_NEAR(r.dataset.info.T_base_lidar.y, T.translation().y(), 1e-12);
  EXPECT_NEAR(r.dataset.info.T_base_lidar.yaw, -0.3, 1e-12);
  EXPECT_EQ(r.dataset.info.config["lidar_mount_from"], "tf chassis -> base_link -> laser");
}

/// Each beam of every imported scan, put in the base frame with the imported 2D mount, lands on
/// the beam's 3D point (range along its angle in the laser frame) mapped by T_base_laser.
void expectPointsInBase(const ImportResult& r, const Eigen::Isometry3d& T_base_laser) {
  for (const ScanRecord& rec : r.dataset.scans) {
    ASSERT_EQ(rec.scan.size(), 8u);
    for (std::size_t i = 0; i < 8; ++i) {
      const double a = double(-1.0f) + double(i) * double(0.25f);  // the message's float angles
      const Eigen::Vector3d p_base =
          T_base_laser *
          Eigen::Vector3d(test::testRange(i) * std::cos(a), test::testRange(i) * std::sin(a), 0.0);
      const Eigen::Vector2d got = r.dataset.info.T_base_lidar * rec.scan.point(i);
      EXPECT_NEAR(got.x(), p_base.x(), 1e-9) << i;
      EXPECT_NEAR(got.y(), p_base.y(), 1e-9) << i;
    }
  }
}

TEST(ImportTf, UpsideDownLidarBecomesAMirroredScanWithTheSamePointsInTheBase) {
  const Eigen::Isometry3d T_up = pose3(0.2, -0.1, 0.3, 0.0, 0.0, 0.4);
  const Eigen::Isometry3d T_down = pose3(0.2, -0.1, 0.3, std::numbers::pi, 0.0, 0.4);  // roll = pi
  test::RobotBagParams b;
  b.tf_static = {transform("base_link", "laser", T_down)};
  const ImportResult r = importMcap(test::robotBag(b), "tf.mcap", withGeometry());
  EXPECT_EQ(r.dataset.info.config["lidar_upside_down"], "true");
  EXPECT_NEAR(r.dataset.info.T_base_lidar.yaw, 0.4, 1e-12);
  // Angles negated, beams kept in the order (and at the times) they were taken.
  const LaserScan& s = r.dataset.scans[0].scan;
  EXPECT_EQ(s.angle_min_rad, 1.0);
  EXPECT_EQ(s.angle_increment_rad, -0.25);
  EXPECT_EQ(s.ranges_m[0], test::testRange(0));
  EXPECT_EQ(s.time_increment_s, double(1e-3f));
  expectPointsInBase(r, T_down);
  bool noted = false;
  for (const auto& n : r.notes) noted = noted || n.find("upside down") != std::string::npos;
  EXPECT_TRUE(noted);

  // The same beams from a level mount are not mirrored: the check above tells them apart (the
  // level scan's points differ from the upside-down ones by up to metres).
  b.tf_static = {transform("base_link", "laser", T_up)};
  const ImportResult level = importMcap(test::robotBag(b), "tf.mcap", withGeometry());
  EXPECT_EQ(level.dataset.scans[0].scan.angle_increment_rad, 0.25);
  EXPECT_EQ(level.dataset.info.config.count("lidar_upside_down"), 0u);
  expectPointsInBase(level, T_up);
  EXPECT_GT((T_up * Eigen::Vector3d(2.75 * std::cos(0.75), 2.75 * std::sin(0.75), 0) -
             T_down * Eigen::Vector3d(2.75 * std::cos(0.75), 2.75 * std::sin(0.75), 0))
                .norm(),
            1.0);
}

TEST(ImportTf, ATiltOverTwoDegreesIsRefusedNamingTheFrames) {
  test::RobotBagParams b;
  b.tf_static = {
      transform("base_link", "laser", pose3(0.2, 0.0, 0.3, 0.0, 5 * std::numbers::pi / 180, 0.0))};
  const std::string e = errorOf(test::robotBag(b), withGeometry());
  EXPECT_NE(e.find("tf base_link -> laser"), std::string::npos) << e;
  EXPECT_NE(e.find("tilted 5.00 deg"), std::string::npos) << e;
  EXPECT_NE(e.find("pitch 5.00 deg"), std::string::npos) << e;
  // 1.5 degrees of roll is inside the bound: read as level.
  b.tf_static = {
      transform("base_link", "laser", pose3(0.2, 0.0, 0.3, 1.5 * std::numbers::pi / 180, 0, 0))};
  EXPECT_NEAR(importMcap(test::robotBag(b), "tf.mcap", withGeometry()).dataset.info.T_base_lidar.x,
              0.2, 1e-12);
  // Upside down and tilted 5 degrees is refused as well.
  b.tf_static = {
      transform("base_link", "laser",
                pose3(0.2, 0.0, 0.3, std::numbers::pi - 5 * std::numbers::pi / 180, 0, 0))};
  EXPECT_NE(errorOf(test::robotBag(b), withGeometry()).find("tilted 5.00 deg"), std::string::npos);
}

TEST(ImportTf, ABaseFrameNotConnectedToTheLaserIsRefusedUnlessChosen) {
  test::RobotBagParams b;
  b.tf_static = {transform("robot_base", "laser", pose3(0.1, 0.0, 0.2, 0.0, 0.0, 0.0))};
  const std::string e = errorOf(test::robotBag(b), withGeometry());
  EXPECT_NE(e.find("no path from base_link to the scans' frame laser"), std::string::npos) << e;
  EXPECT_NE(e.find("--base-frame"), std::string::npos) << e;
  ImportParams p = withGeometry();
  p.base_frame = "robot_base";
  EXPECT_NEAR(importMcap(test::robotBag(b), "tf.mcap", p).dataset.info.T_base_lidar.x, 0.1, 1e-12);
  // A frame with two parents is refused naming both.
  b.tf_static.push_back(transform("base_link", "laser", pose3(0, 0, 0, 0, 0, 0)));
  EXPECT_NE(errorOf(test::robotBag(b), p).find("two parents"), std::string::npos);
}

/// The imported gyro and accelerometer of a bag whose IMU sits at `T_base_imu`, and its notes.
ImportResult importWithImu(const Eigen::Isometry3d& T_base_imu) {
  test::RobotBagParams b;
  b.imu_frame = "imu_link";
  b.tf_static = {transform("base_link", "imu_link", T_base_imu)};
  return importMcap(test::robotBag(b), "tf.mcap", withGeometry());
}

bool noted(const ImportResult& r, const std::string& part) {
  for (const auto& n : r.notes)
    if (n.find(part) != std::string::npos) return true;
  return false;
}

// The base turns about its z axis: an IMU's gyro reads R_zz w of it, so the yaw rate is gyro_z /
// R_zz at any tilt (the bag's IMU reads 0.3 rad/s about its own z).
TEST(ImportTf, TheGyroIsTurnedIntoTheBaseFrame) {
  const ImportResult level = importWithImu(pose3(0.1, 0.0, 0.05, 0.0, 0.0, 0.5));  // yawed
  ASSERT_FALSE(level.dataset.imu.empty());
  EXPECT_EQ(level.dataset.imu[0].gyro_z_radps, 0.3);
  EXPECT_NEAR(level.dataset.imu[0].accel_x_mps2, std::cos(0.5) - 2.0 * std::sin(0.5), 1e-12);
  EXPECT_NEAR(level.dataset.imu[0].accel_y_mps2, std::sin(0.5) + 2.0 * std::cos(0.5), 1e-12);
  EXPECT_EQ(level.dataset.info.config["imu_mount_from"], "tf base_link -> imu_link");

  const ImportResult down = importWithImu(pose3(0.0, 0.0, 0.05, std::numbers::pi, 0.0, 0.0));
  EXPECT_NEAR(down.dataset.imu[0].gyro_z_radps, -0.3, 1e-12);
  EXPECT_NEAR(down.dataset.imu[0].accel_y_mps2, -2.0, 1e-12);
  EXPECT_TRUE(noted(down, "IMU mounted upside down"));

  const ImportResult tilted = importWithImu(pose3(0.0, 0.0, 0.05, 0.0, 0.4, 0.0));  // pitch
  EXPECT_NEAR(tilted.dataset.imu[0].gyro_z_radps, 0.3 / std::cos(0.4), 1e-12);
  EXPECT_EQ(tilted.dataset.imu[0].accel_x_mps2, 1.0);  // kept: its gravity part is unknown
  EXPECT_TRUE(noted(tilted, "is tilted"));

  const ImportResult sideways = importWithImu(pose3(0.0, 0.0, 0.05, 1.3, 0.0, 0.0));
  EXPECT_TRUE(sideways.dataset.imu.empty());
  EXPECT_TRUE(noted(sideways, "left out"));
}

}  // namespace
}  // namespace slamprep::eval
