// End to end: the simulator (kinematic mode, default world, figure eight plus spins) writes a
// dataset; calibration from ground-truth lidar motion recovers the true geometry and mount.
#include <gtest/gtest.h>

#include <numbers>

#include "slamprep/algo/calibration/calibration.hpp"
#include "slamprep/algo/calibration/dataset_motion.hpp"
#include "slamprep/sim/drive/simulator.hpp"

namespace slamprep::algo {
namespace {

class EndToEnd : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    sim::SimConfig config;  // default world and scenario (figure eight, spins, two circles)
    config.mode = sim::SimMode::kinematic;
    dataset_ = new Dataset(sim::simulate(config).dataset);
    // The default policy, as `slamprep calibrate` and the bench cut them: every scan match.
    intervals_ = new std::vector<CalibrationInterval>(
        buildIntervals(*dataset_, {lidarPosesFromGroundTruth(*dataset_)}, IntervalParams{})
            .intervals);
  }
  static void TearDownTestSuite() {
    delete dataset_;
    delete intervals_;
  }

  // Bounds at 3-5x what each method reaches here, so a real loss of accuracy fails. With exact
  // kinematics and ground-truth motion the remaining error is encoder quantisation (2 pi / 4096
  // per tick) and the constant-rate interpolation inside 10 ms encoder steps at interval ends.
  // Reached (the run is deterministic; no sensor noise enters): joint 4.6e-5, 8.0e-5, 5.7e-5
  // relative (r_L, r_R, b), mount 2.1 um, 4.2 um, 1.4e-4 deg; ceres 2.9e-6, 3.6e-6, 1.6e-5,
  // 0.9 um, 0.8 um, 1.0e-4 deg.
  struct Bounds {
    double geometry_rel;
    double mount_m;
    double yaw_deg;
  };
  static void expectTruth(const CalibrationResult& r, const Bounds& bound) {
    ASSERT_TRUE(r.ok) << r.reason;
    const DiffDriveParams& truth = *dataset_->info.true_geometry;
    const SE2& mount = dataset_->info.T_base_lidar;
    EXPECT_LT(std::abs(r.geometry.radius_left_m / truth.radius_left_m - 1), bound.geometry_rel);
    EXPECT_LT(std::abs(r.geometry.radius_right_m / truth.radius_right_m - 1), bound.geometry_rel);
    EXPECT_LT(std::abs(r.geometry.wheel_base_m / truth.wheel_base_m - 1), bound.geometry_rel);
    EXPECT_LT(std::abs(r.T_base_lidar.x - mount.x), bound.mount_m);
    EXPECT_LT(std::abs(r.T_base_lidar.y - mount.y), bound.mount_m);
    EXPECT_LT(std::abs(normalizeAngle(r.T_base_lidar.yaw - mount.yaw)),
              bound.yaw_deg * std::numbers::pi / 180.0);
  }

  static Dataset* dataset_;
  static std::vector<CalibrationInterval>* intervals_;
};

Dataset* EndToEnd::dataset_ = nullptr;
std::vector<CalibrationInterval>* EndToEnd::intervals_ = nullptr;

TEST_F(EndToEnd, EnoughIntervals) {
  ASSERT_TRUE(dataset_->hasTruth());
  // 582 scans: 581 matches, 21 of them standing still.
  EXPECT_EQ(intervals_->size(), 560u);
}

TEST_F(EndToEnd, JointRecoversGeometryAndMount) {
  expectTruth(calibrateJoint(*intervals_), {3e-4, 15e-6, 5e-4});
}

TEST_F(EndToEnd, CeresRecoversGeometryAndMount) {
  expectTruth(calibrateCeres(*intervals_), {1e-4, 5e-6, 4e-4});
}

}  // namespace
}  // namespace slamprep::algo
