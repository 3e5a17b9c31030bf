// De-skew on simulated data (Bullet, physics mode): the default room, the 1 m/s, 1 rad/s arc,
// 10 Hz, 720 beams, 1 cm range noise, odometry from the NOMINAL geometry (the robot's belief).
#include <gtest/gtest.h>

#include <cstdio>
#include <map>

#include "slamprep/algo/deskew/sequence.hpp"
#include "slamprep/core/odometry.hpp"
#include "slamprep/eval/metrics/deskew_error.hpp"
#include "slamprep/sim/drive/simulator.hpp"

namespace slamprep::algo {
namespace {

void append(std::vector<double>& errors_m, const eval::DeskewErrorResult& scan) {
  errors_m.insert(errors_m.end(), scan.errors_m.begin(), scan.errors_m.end());
}

const Dataset& arcDataset() {
  static const Dataset d = [] {
    sim::SimConfig config;  // defaults: worlds/room.yaml, physics, 10 Hz, 720 beams, 1 cm noise
    config.scenario = "worlds/scenarios/arc.yaml";
    return sim::simulate(config).dataset;
  }();
  return d;
}

/// Mean error over the scans taken at full speed (the arc's ramps excluded: 2 s to 6 s).
eval::ErrorStats meanError(DeskewMethod method, const PoseSeries& odometry) {
  const Dataset& d = arcDataset();
  DeskewInputs in;
  in.odometry = odometry;
  in.imu = d.imu;
  in.groundtruth = d.groundtruth;
  in.T_base_lidar = d.info.T_base_lidar;
  DeskewSequence sequence(method, in, {});
  std::vector<double> errors_m;  // every beam of every counted scan
  for (const ScanRecord& rec : d.scans) {
    const DeskewResult r = sequence.next(rec.scan);
    EXPECT_TRUE(r.ok) << deskewMethodName(method) << " at " << rec.scan.stamp_s << ": " << r.reason;
    if (r.ok && rec.scan.stamp_s >= 2.0 && rec.scan.stamp_s <= 6.0)
      append(errors_m, eval::deskewError(r.p_ref, rec.p_ref_true));
  }
  return eval::summarize(errors_m);
}

/// Relative yaw-rate error of odometry that believes `nominal` on the arc (1 m/s, 1 rad/s):
/// the true wheel rates (w_L, w_R) = truth.wheelRates(v, w) turned into a twist by `nominal`.
double yawRateError(const DiffDriveParams& truth, const DiffDriveParams& nominal) {
  const Eigen::Vector2d rates = truth.wheelRates(1.0, 1.0);
  return nominal.twist(rates.x(), rates.y()).y() / 1.0 - 1.0;
}

// Physics says (docs/deskew.md derives each figure):
// - none: points move ~tau (v + w r) during the scan, ~0.2 m on average, mostly from the turn;
// - odometry methods with the nominal geometry (r_L +2 %, r_R -1.5 %, b +4 %) undo the turn
//   only up to their yaw-rate error, -10.3 % on this arc, so they keep about 10 % of `none`;
// - odom-icp replaces that error by ICP noise (~1 mm); quadratic equals linear at 100 Hz
//   odometry (their difference is micrometres), so "combined <= quadratic <= linear" is asserted
//   with a 5% tolerance between the last two;
// - the oracle uses the simulator's own poses: rounding only.
TEST(DeskewOnSimulatedArc, MethodsRankAsPhysicsSays) {
  const Dataset& d = arcDataset();
  ASSERT_TRUE(d.hasTruth());
  ASSERT_GT(d.scans.size(), 50u);
  std::map<DeskewMethod, double> mean;
  for (DeskewMethod m : allDeskewMethods()) {
    mean[m] = meanError(m, d.odom_nominal).mean;
    std::printf("%-16s %9.3f mm\n", std::string(deskewMethodName(m)).c_str(), mean[m] * 1e3);
  }
  using M = DeskewMethod;
  EXPECT_LT(mean[M::kOracle], 1e-6);
  EXPECT_LT(mean[M::kOracle], mean[M::kOdomIcp]);
  EXPECT_LT(mean[M::kOdomIcp], mean[M::kOdomQuadratic]);
  EXPECT_LT(mean[M::kOdomQuadratic], 1.05 * mean[M::kOdomLinear]);
  EXPECT_GT(mean[M::kNone], 0.1);
  // The residual of the odometry methods is the yaw-rate error's share of `none` (26.1 of 255.7
  // mm, ratio 0.102, against a predicted 0.103); 25 % leaves room for the translation share.
  const double yaw_error = std::abs(yawRateError(*d.info.true_geometry, d.info.nominal_geometry));
  EXPECT_NEAR(yaw_error, 0.103, 0.001);
  EXPECT_NEAR(mean[M::kOdomLinear] / mean[M::kNone], yaw_error, 0.25 * yaw_error);
  // The goals: combined from the nominal geometry <= 2 mm, IMU <= 2 mm, all >= 30x below none
  // except the nominal-geometry odometry methods (the goal grants them the true geometry).
  // Reached: odom-icp 1.06 mm, imu 0.37, const-velocity 0.80, vicp 0.80; the bounds sit at 2-4x.
  EXPECT_LT(mean[M::kOdomIcp], 0.002);
  EXPECT_LT(mean[M::kImu], 0.0012);
  EXPECT_LT(mean[M::kConstVelocity], 0.003);
  EXPECT_LT(mean[M::kVicp], 0.003);
  for (M m : {M::kOdomIcp, M::kImu, M::kConstVelocity, M::kVicp})
    EXPECT_LT(30.0 * mean[m], mean[M::kNone]) << deskewMethodName(m);
}

// With the true geometry the odometry methods are left with slip and tick quantisation:
// the goal is at most 1 mm mean.
TEST(DeskewOnSimulatedArc, OdometryWithTrueGeometryWithin1mm) {
  const Dataset& d = arcDataset();
  const PoseSeries odom_true =
      integrateEncoders(d.encoders, *d.info.true_geometry, d.info.ticks_per_revolution);
  for (DeskewMethod m : {DeskewMethod::kOdomLinear, DeskewMethod::kOdomQuadratic}) {
    const double e = meanError(m, odom_true).mean;
    std::printf("%-16s true geometry %9.3f mm\n", std::string(deskewMethodName(m)).c_str(),
                e * 1e3);
    EXPECT_LT(e, 0.001) << deskewMethodName(m);
  }
}

}  // namespace
}  // namespace slamprep::algo
