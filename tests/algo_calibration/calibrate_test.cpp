// The method registry (names, properties, the best-result rule) and the one dispatcher.
#include <gtest/gtest.h>

#include "slamprep/algo/calibration/calibration.hpp"
#include "synthetic.hpp"

namespace slamprep::algo {
namespace {

using testing::makeIntervals;
using testing::SyntheticSpec;

TEST(CalibrationMethod, NamesRoundTripInRunOrder) {
  const std::vector<std::string> expected = {"direct", "model", "joint", "ceres", "umbmark"};
  EXPECT_EQ(calibrationMethodNames(), expected);
  for (CalibrationMethod m : allCalibrationMethods())
    EXPECT_EQ(parseCalibrationMethod(calibrationMethodName(m)), m);
  EXPECT_FALSE(parseCalibrationMethod("all"));
  EXPECT_FALSE(parseCalibrationMethod("Joint"));
  EXPECT_EQ(joinCalibrationMethodNames(intervalMethods(), ", "), "direct, model, joint, ceres");
}

TEST(CalibrationMethod, PropertiesAndPreference) {
  EXPECT_FALSE(isIntervalMethod(CalibrationMethod::kUmbmark));
  EXPECT_TRUE(isIntervalMethod(CalibrationMethod::kDirect));
  EXPECT_TRUE(estimatesMount(CalibrationMethod::kJoint));
  EXPECT_TRUE(estimatesMount(CalibrationMethod::kCeres));
  EXPECT_FALSE(estimatesMount(CalibrationMethod::kModel));
  EXPECT_EQ(joinCalibrationMethodNames(calibrationPreference(), ">"),
            "ceres>joint>model>direct>umbmark");
  EXPECT_LT(preferenceRank(CalibrationMethod::kCeres), preferenceRank(CalibrationMethod::kJoint));
}

CalibrationRun run(CalibrationMethod method, bool ok) {
  CalibrationRun r;
  r.method = method;
  r.result.ok = ok;
  return r;
}

TEST(BestRun, FirstOkInPreferenceOrder) {
  using M = CalibrationMethod;
  EXPECT_EQ(bestRun({}), nullptr);
  EXPECT_EQ(bestRun({run(M::kCeres, false), run(M::kJoint, false)}), nullptr);
  std::vector<CalibrationRun> runs = {run(M::kDirect, true), run(M::kModel, true),
                                      run(M::kJoint, true), run(M::kCeres, false),
                                      run(M::kUmbmark, true)};
  EXPECT_EQ(bestRun(runs), &runs[2]);  // ceres refused: joint
  runs[3].result.ok = true;
  EXPECT_EQ(bestRun(runs), &runs[3]);
  runs = {run(M::kUmbmark, true), run(M::kDirect, true), run(M::kDirect, true)};
  EXPECT_EQ(bestRun(runs), &runs[1]);  // the first of two equal methods
}

TEST(Calibrate, DispatchesToTheMethods) {
  const SyntheticSpec spec;
  CalibrationInput input;
  input.intervals = makeIntervals(spec);
  input.nominal = DiffDriveParams{0.1, 0.1, 0.5};
  const CalibrationRun joint = calibrate(CalibrationMethod::kJoint, input);
  const JointResult direct_call = calibrateJoint(input.intervals);
  ASSERT_TRUE(joint.result.ok) << joint.result.reason;
  EXPECT_EQ(joint.result.geometry.wheel_base_m, direct_call.geometry.wheel_base_m);
  EXPECT_EQ(joint.result.T_base_lidar.yaw, direct_call.T_base_lidar.yaw);
  EXPECT_FALSE(joint.time_offset_s);
  // Run together, ceres starts from the same joint result it computes alone: identical bits.
  const CalibrationRun ceres = calibrate(CalibrationMethod::kCeres, input);
  const auto runs = calibrate({CalibrationMethod::kJoint, CalibrationMethod::kCeres}, input);
  ASSERT_EQ(runs.size(), 2u);
  EXPECT_EQ(runs[0].method, CalibrationMethod::kJoint);
  EXPECT_EQ(runs[1].method, CalibrationMethod::kCeres);
  ASSERT_TRUE(runs[1].result.ok) << runs[1].result.reason;
  EXPECT_EQ(runs[1].result.geometry.radius_left_m, ceres.result.geometry.radius_left_m);
  EXPECT_EQ(runs[1].result.T_base_lidar.x, ceres.result.T_base_lidar.x);
  EXPECT_EQ(runs[0].result.geometry.wheel_base_m, joint.result.geometry.wheel_base_m);
}

TEST(Calibrate, CeresReportsTheTimeOffsetOnlyWhenEstimated) {
  CalibrationInput input;
  input.intervals = makeIntervals(SyntheticSpec{});
  CalibrationParams params;
  params.ceres.estimate_time_offset = true;
  const CalibrationRun r = calibrate(CalibrationMethod::kCeres, input, params);
  ASSERT_TRUE(r.result.ok) << r.result.reason;
  ASSERT_TRUE(r.time_offset_s);
  EXPECT_NEAR(*r.time_offset_s, 0.0, 1e-6);  // noiseless, no offset simulated
}

// A lidar facing backwards (a Neato's): model and direct, which assume it at the centre, read
// the wheels as driving the wrong way; given the mount they recover the geometry (model exactly,
// direct to its small-increment approximation, 1 % as with a centred lidar in methods_test), and
// joint and ceres, which estimate the mount, are not changed by it.
TEST(Calibrate, AKnownMountIsTakenByTheMethodsThatDoNotEstimateOne) {
  SyntheticSpec spec;
  spec.T_base_lidar = SE2(-0.2, 0.05, 3.0);
  CalibrationInput input;
  input.intervals = makeIntervals(spec);
  input.nominal = DiffDriveParams{0.1, 0.1, 0.5};
  EXPECT_FALSE(calibrate(CalibrationMethod::kModel, input).result.ok);
  const CalibrationRun joint = calibrate(CalibrationMethod::kJoint, input);
  input.known_T_base_lidar = spec.T_base_lidar;
  for (const auto& [m, tolerance] :
       {std::pair{CalibrationMethod::kModel, 1e-9}, std::pair{CalibrationMethod::kDirect, 1e-2}}) {
    const CalibrationRun r = calibrate(m, input);
    ASSERT_TRUE(r.result.ok) << r.result.reason;
    EXPECT_LT(testing::rel(r.result.geometry.radius_left_m, spec.truth.radius_left_m), tolerance);
    EXPECT_LT(testing::rel(r.result.geometry.radius_right_m, spec.truth.radius_right_m), tolerance);
    EXPECT_LT(testing::rel(r.result.geometry.wheel_base_m, spec.truth.wheel_base_m), tolerance);
  }
  const CalibrationRun joint_given = calibrate(CalibrationMethod::kJoint, input);
  EXPECT_EQ(joint_given.result.geometry.wheel_base_m, joint.result.geometry.wheel_base_m);
  EXPECT_EQ(joint_given.result.T_base_lidar.x, joint.result.T_base_lidar.x);
}

// A fit whose 1-sigma exceeds the limit fraction of its estimate is refused as undetermined,
// naming the parameter; the same fit within the limit, or noiseless (sigma 0), stands.
TEST(Calibrate, AnEstimateItsSigmaSwampsIsRefusedAsUndetermined) {
  SyntheticSpec spec;
  spec.T_base_lidar = SE2();  // model's assumption
  spec.sigma_x_m = spec.sigma_y_m = 0.002;
  spec.sigma_theta_rad = 0.002;
  CalibrationInput input;
  input.intervals = makeIntervals(spec);
  CalibrationParams params;
  const CalibrationRun fit = calibrate(CalibrationMethod::kModel, input, params);
  ASSERT_TRUE(fit.result.ok) << fit.result.reason;
  const double relative_b = fit.result.sigma()(2) / fit.result.geometry.wheel_base_m;
  ASSERT_GT(relative_b, 0.0);
  ASSERT_LT(relative_b, params.max_relative_sigma);
  params.max_relative_sigma = 0.5 * relative_b;  // b's sigma now beyond the limit
  const CalibrationRun refused = calibrate(CalibrationMethod::kModel, input, params);
  EXPECT_FALSE(refused.result.ok);
  EXPECT_NE(refused.result.reason.find("undetermined: "), std::string::npos)
      << refused.result.reason;
  spec.sigma_x_m = spec.sigma_y_m = spec.sigma_theta_rad = 0.0;
  input.intervals = makeIntervals(spec);
  EXPECT_TRUE(calibrate(CalibrationMethod::kModel, input, params).result.ok);
}

TEST(Calibrate, RefusesWhatLacksItsInput) {
  const CalibrationInput empty;
  const CalibrationRun direct = calibrate(CalibrationMethod::kDirect, empty);
  EXPECT_FALSE(direct.result.ok);
  EXPECT_NE(direct.result.reason.find("nominal geometry"), std::string::npos);
  const CalibrationRun umbmark = calibrate(CalibrationMethod::kUmbmark, empty);
  EXPECT_FALSE(umbmark.result.ok);
  EXPECT_NE(umbmark.result.reason.find("no UMBmark square runs"), std::string::npos);
  const CalibrationRun joint = calibrate(CalibrationMethod::kJoint, empty);  // no intervals
  EXPECT_FALSE(joint.result.ok);
  EXPECT_FALSE(joint.result.reason.empty());
}

}  // namespace
}  // namespace slamprep::algo
