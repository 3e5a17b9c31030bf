// Noisy synthetic data, 200 seeded trials per method: the estimates are unbiased and the reported
// 1-sigma matches the observed spread.
#include <gtest/gtest.h>

#include <functional>

#include "algo/calibration/calibration.hpp"
#include "synthetic.hpp"

namespace slamprep::algo {
namespace {

using testing::makeIntervals;
using testing::SyntheticSpec;

constexpr int kTrials = 200;

Eigen::VectorXd truthVector(const SyntheticSpec& spec, bool mount) {
  Eigen::VectorXd v(mount ? 6 : 3);
  v.head<3>() << spec.truth.radius_left_m, spec.truth.radius_right_m, spec.truth.wheel_base_m;
  if (mount) v.tail<3>() << spec.T_base_lidar.x, spec.T_base_lidar.y, spec.T_base_lidar.yaw;
  return v;
}

Eigen::VectorXd estimateVector(const CalibrationResult& r) {
  Eigen::VectorXd v(r.estimates_mount ? 6 : 3);
  v.head<3>() << r.geometry.radius_left_m, r.geometry.radius_right_m, r.geometry.wheel_base_m;
  if (r.estimates_mount) v.tail<3>() << r.T_base_lidar.x, r.T_base_lidar.y, r.T_base_lidar.yaw;
  return v;
}

// Runs `method` on kTrials seeded data sets and checks, per parameter:
// - unbiased: |mean error| < 4 * std / sqrt(200), a 4-sigma bound on the sample mean;
// - calibrated: observed std / rms(reported sigma) within [0.8, 1.2]; the sample std of 200
//   draws has a relative standard error of 1/sqrt(2 * 199) = 5%, so 20% is a 4-sigma margin.
void checkCalibrated(
    const std::string& name, SyntheticSpec spec,
    const std::function<CalibrationResult(const std::vector<CalibrationInterval>&)>& method) {
  SCOPED_TRACE(name);
  std::vector<Eigen::VectorXd> errors, sigmas;
  for (int t = 0; t < kTrials; ++t) {
    spec.seed = 1000 + t;
    const CalibrationResult r = method(makeIntervals(spec));
    ASSERT_TRUE(r.ok) << r.reason;
    errors.push_back(estimateVector(r) - truthVector(spec, r.estimates_mount));
    sigmas.push_back(r.sigma());
  }
  const Eigen::Index m = errors[0].size();
  Eigen::VectorXd mean = Eigen::VectorXd::Zero(m), var = mean, sig2 = mean;
  for (int t = 0; t < kTrials; ++t) {
    mean += errors[t] / kTrials;
    sig2 += sigmas[t].cwiseAbs2() / kTrials;
  }
  for (int t = 0; t < kTrials; ++t) var += (errors[t] - mean).cwiseAbs2() / (kTrials - 1);
  const char* names[] = {"r_L", "r_R", "b", "lidar_x", "lidar_y", "lidar_yaw"};
  for (Eigen::Index i = 0; i < m; ++i) {
    const double std_obs = std::sqrt(var(i)), sigma_rep = std::sqrt(sig2(i));
    std::printf("  %-8s %-10s bias %+.3e  observed std %.3e  reported sigma %.3e  ratio %.3f\n",
                name.c_str(), names[i], mean(i), std_obs, sigma_rep, std_obs / sigma_rep);
    EXPECT_LT(std::abs(mean(i)), 4.0 * std_obs / std::sqrt(kTrials)) << names[i];
    EXPECT_NEAR(std_obs / sigma_rep, 1.0, 0.2) << names[i];
  }
}

SyntheticSpec noisy() {
  SyntheticSpec spec;
  spec.intervals = 80;
  spec.sigma_x_m = 0.003;  // per axis: the noise frame matters
  spec.sigma_y_m = 0.001;
  spec.sigma_theta_rad = 0.002;
  return spec;
}

TEST(Noise, ModelBasedIsUnbiasedAndCalibrated) {
  SyntheticSpec spec = noisy();
  spec.T_base_lidar = SE2();
  checkCalibrated("model", spec, [](const auto& in) { return calibrateModelBased(in); });
}

TEST(Noise, JointIsUnbiasedAndCalibrated) {
  checkCalibrated("joint", noisy(), [](const auto& in) { return calibrateJoint(in); });
}

TEST(Noise, CeresIsUnbiasedAndCalibrated) {
  checkCalibrated("ceres", noisy(), [](const auto& in) { return calibrateCeres(in); });
}

TEST(Noise, DirectLinearIsUnbiasedAndCalibratedForAUniformScale) {
  SyntheticSpec spec = noisy();
  spec.T_base_lidar = SE2();
  spec.truth = {0.102, 0.102, 0.51};
  DirectLinearParams params;
  params.nominal = {0.1, 0.1, 0.5};
  checkCalibrated("direct", spec,
                  [&](const auto& in) { return calibrateDirectLinear(in, params); });
}

}  // namespace
}  // namespace slamprep::algo
