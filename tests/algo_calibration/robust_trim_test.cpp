// Robust screening (robust_trim.hpp): clean synthetic intervals plus 5 % odometry glitches. Every
// interval method must drop exactly the glitches and so return the clean-data fit, and the same
// data without screening must be off.
#include <gtest/gtest.h>

#include <algorithm>

#include "slamprep/algo/calibration/calibrate.hpp"
#include "slamprep/algo/calibration/calibration_json.hpp"
#include "slamprep/algo/calibration/joint_censi.hpp"
#include "slamprep/core/error.hpp"
#include "synthetic.hpp"

namespace slamprep::algo {
namespace {

using testing::makeIntervals;
using testing::SyntheticSpec;

constexpr int kClean = 76;
constexpr int kGlitches = 4;  // 5 % of the 80 intervals

SyntheticSpec specFor(CalibrationMethod method) {
  SyntheticSpec spec;
  spec.intervals = kClean;
  spec.sigma_x_m = 3e-3;  // per axis, as the scan matcher's noise
  spec.sigma_y_m = 1e-3;
  spec.sigma_theta_rad = 2e-3;
  // direct and model assume the lidar at the centre.
  if (!estimatesMount(method)) spec.T_base_lidar = SE2();
  return spec;
}

// A glitch: the odometry jumped (0.4 m forward or 40 deg) while the lidar saw the usual motion.
std::vector<CalibrationInterval> withGlitches(const std::vector<CalibrationInterval>& clean,
                                              std::vector<double>* glitch_starts) {
  std::vector<CalibrationInterval> out;
  for (int k = 0; k < static_cast<int>(clean.size()); ++k) {
    out.push_back(clean[k]);
    if (k % 19 != 9) continue;
    CalibrationInterval glitch = clean[k];
    EncoderStep& step = glitch.steps[glitch.steps.size() / 2];
    if (out.size() % 2 == 0) {
      step.dphi_left_rad += 4.0;  // 0.4 m more on both wheels
      step.dphi_right_rad += 4.0;
    } else {
      step.dphi_left_rad -= 3.5;  // a spin of about 40 deg
      step.dphi_right_rad += 3.5;
    }
    glitch_starts->push_back(glitch.t_start_s);
    out.push_back(std::move(glitch));
  }
  return out;
}

CalibrationInput inputOf(std::vector<CalibrationInterval> intervals) {
  return {std::move(intervals), DiffDriveParams{0.1, 0.1, 0.5}, {}, {}, std::nullopt, std::nullopt};
}

double worstRelativeError(const DiffDriveParams& a, const DiffDriveParams& truth) {
  return std::max({testing::rel(a.radius_left_m, truth.radius_left_m),
                   testing::rel(a.radius_right_m, truth.radius_right_m),
                   testing::rel(a.wheel_base_m, truth.wheel_base_m)});
}

class RobustTrim : public ::testing::TestWithParam<CalibrationMethod> {};

TEST_P(RobustTrim, DropsExactlyTheGlitchesAndRecoversTheCleanFit) {
  const CalibrationMethod method = GetParam();
  const SyntheticSpec spec = specFor(method);
  const auto clean = makeIntervals(spec);
  std::vector<double> glitch_starts;
  const auto glitchy = withGlitches(clean, &glitch_starts);
  ASSERT_EQ(glitch_starts.size(), static_cast<std::size_t>(kGlitches));

  const CalibrationRun on_clean = calibrate(method, inputOf(clean));
  const CalibrationRun robust = calibrate(method, inputOf(glitchy));
  CalibrationParams off;
  off.trim.enabled = false;
  const CalibrationRun plain = calibrate(method, inputOf(glitchy), off);
  ASSERT_TRUE(on_clean.result.ok) << on_clean.result.reason;
  ASSERT_TRUE(robust.result.ok) << robust.result.reason;

  // Clean data: nothing screened out.
  EXPECT_TRUE(on_clean.result.trimmed_worst.empty());
  const double clean_error = worstRelativeError(on_clean.result.geometry, spec.truth);
  EXPECT_LT(clean_error, 0.01);

  // Glitchy data: the four glitches and nothing else, so the fit is the clean one.
  EXPECT_EQ(robust.result.intervals_trimmed - on_clean.result.intervals_trimmed, kGlitches);
  ASSERT_EQ(robust.result.trimmed_worst.size(), static_cast<std::size_t>(kGlitches));
  std::vector<double> reported;
  for (const TrimmedInterval& t : robust.result.trimmed_worst) {
    reported.push_back(t.t0_s);
    EXPECT_GT(t.residual_sigmas, 20.0) << t.reason;
    EXPECT_FALSE(t.reason.empty());
  }
  std::sort(reported.begin(), reported.end());
  EXPECT_EQ(reported, glitch_starts);
  const DiffDriveParams& g = robust.result.geometry;
  const DiffDriveParams& c = on_clean.result.geometry;
  EXPECT_NEAR(g.radius_left_m, c.radius_left_m, 1e-12);
  EXPECT_NEAR(g.radius_right_m, c.radius_right_m, 1e-12);
  EXPECT_NEAR(g.wheel_base_m, c.wheel_base_m, 1e-12);

  // Without screening the glitches pull the fit far off (or it refuses).
  if (plain.result.ok) {
    EXPECT_GT(worstRelativeError(plain.result.geometry, spec.truth), 5.0 * clean_error)
        << "clean " << clean_error;
  }
}

INSTANTIATE_TEST_SUITE_P(IntervalMethods, RobustTrim,
                         ::testing::Values(CalibrationMethod::kDirect, CalibrationMethod::kModel,
                                           CalibrationMethod::kJoint, CalibrationMethod::kCeres),
                         [](const auto& info) {
                           return std::string(calibrationMethodName(info.param));
                         });

// Two glitches among 40 intervals, and a method that needs all but one: the fit on all stands,
// the refit after dropping the two has too few left. The refusal gives the fit that stood, so
// that a reader does not take the refit's complaint (here too few intervals; on a real Neato
// recording "channels swapped") for the robot's.
TEST(RobustTrim, ARefitThatFailsAfterDroppingNamesTheFitThatStood) {
  SyntheticSpec spec = specFor(CalibrationMethod::kJoint);
  spec.intervals = 40;
  std::vector<CalibrationInterval> intervals = makeIntervals(spec);
  for (const int k : {12, 31}) {  // 0.4 m more on both wheels, the lidar saw the usual motion
    intervals[k].steps.front().dphi_left_rad += 4.0;
    intervals[k].steps.front().dphi_right_rad += 4.0;
  }
  CalibrationParams params;
  params.joint.min_intervals = 39;
  params.trim.enabled = false;
  // Untrimmed, the two glitches are most of the sandwich's sigma (r_L 20 %): not undetermined.
  params.max_relative_sigma = 0.0;
  ASSERT_TRUE(calibrate(CalibrationMethod::kJoint, inputOf(intervals), params).result.ok);
  params.trim.enabled = true;
  const CalibrationRun r = calibrate(CalibrationMethod::kJoint, inputOf(intervals), params);
  ASSERT_FALSE(r.result.ok);
  EXPECT_NE(r.result.reason.find("after dropping 2 outlier intervals: too few intervals"),
            std::string::npos)
      << r.result.reason;
  EXPECT_NE(r.result.reason.find("before dropping them the fit stood (r_L "), std::string::npos)
      << r.result.reason;
}

TEST(RobustTrim, SharedJointFitGivesTheSameResultAsSeparateRuns) {
  const SyntheticSpec spec = specFor(CalibrationMethod::kJoint);
  std::vector<double> starts;
  const CalibrationInput input = inputOf(withGlitches(makeIntervals(spec), &starts));
  const auto both = calibrate({CalibrationMethod::kJoint, CalibrationMethod::kCeres}, input);
  const CalibrationRun ceres = calibrate(CalibrationMethod::kCeres, input);
  ASSERT_TRUE(both[1].result.ok);
  EXPECT_EQ(both[1].result.geometry.wheel_base_m, ceres.result.geometry.wheel_base_m);
  EXPECT_EQ(both[1].result.intervals_trimmed, ceres.result.intervals_trimmed);
}

TEST(RobustTrim, JsonCarriesTrimmedIntervalsAndTheOdometryReference) {
  const SyntheticSpec spec = specFor(CalibrationMethod::kJoint);
  std::vector<double> starts;
  CalibrationRun run =
      calibrate(CalibrationMethod::kJoint, inputOf(withGlitches(makeIntervals(spec), &starts)));
  run.relative_to_odometry = DiffDriveParams{0.1, 0.1, 0.5};
  const std::string text = formatCalibrationJson({run}, std::nullopt);
  EXPECT_NE(text.find("\"intervals_trimmed\": 4"), std::string::npos) << text;
  EXPECT_NE(text.find("\"meaning\""), std::string::npos);
  const CalibrationFile file = parseCalibrationJson(text, "cal.json");
  ASSERT_EQ(file.runs.size(), 1u);
  const CalibrationResult& back = file.runs[0].result;
  EXPECT_EQ(back.intervals_trimmed, 4);
  ASSERT_EQ(back.trimmed_worst.size(), run.result.trimmed_worst.size());
  for (std::size_t i = 0; i < back.trimmed_worst.size(); ++i) {
    EXPECT_EQ(back.trimmed_worst[i].t0_s, run.result.trimmed_worst[i].t0_s);
    EXPECT_EQ(back.trimmed_worst[i].t1_s, run.result.trimmed_worst[i].t1_s);
    EXPECT_EQ(back.trimmed_worst[i].reason, run.result.trimmed_worst[i].reason);
    EXPECT_EQ(back.trimmed_worst[i].residual_sigmas, run.result.trimmed_worst[i].residual_sigmas);
  }
  ASSERT_TRUE(file.runs[0].relative_to_odometry);
  EXPECT_EQ(file.runs[0].relative_to_odometry->wheel_base_m, 0.5);
  EXPECT_THROW(parseCalibrationJson(R"([{"method":"joint","ok":false,"trimmed_worst":3}])", "c"),
               InputError);
}

// Joint's own trimming (before the screening around every method): with 5 % trimmed per round
// it must drop the glitches first, so its fit is close to the clean-data fit. A trimming that
// sorted the wrong way would keep the glitches and drop the best intervals.
TEST(JointTrim, DropsTheWorstIntervalsFirst) {
  const SyntheticSpec spec = specFor(CalibrationMethod::kJoint);
  std::vector<double> starts;
  const auto glitchy = withGlitches(makeIntervals(spec), &starts);
  const JointResult clean = calibrateJoint(makeIntervals(spec));
  JointParams params;
  params.trim_fraction = 0.05;  // 4 of the 80 intervals in the first round
  const JointResult trimmed = calibrateJoint(glitchy, params);
  ASSERT_TRUE(clean.ok && trimmed.ok) << trimmed.reason;
  const double clean_error = worstRelativeError(clean.geometry, spec.truth);
  EXPECT_LT(worstRelativeError(trimmed.geometry, spec.truth), 3.0 * clean_error + 1e-4);
}

}  // namespace
}  // namespace slamprep::algo
