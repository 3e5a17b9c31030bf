// Held-out validation as a verdict (algo/calibration/validation_flag.hpp): a calibrated geometry
// that predicts the held-out part worse than the nominal one is flagged, beyond 10 % + a floor.
#include "slamprep/algo/calibration/validation_flag.hpp"

#include <gtest/gtest.h>

namespace slamprep::algo {
namespace {

ValidationFigures figures(double raw_m, double raw_deg, double cal_m, double cal_deg) {
  return ValidationFigures{0.3, {raw_m, raw_deg}, {cal_m, cal_deg}, std::nullopt};
}

TEST(ValidationFlag, NoFlagWhereTheCalibratedGeometryIsBetterOrAsGood) {
  EXPECT_FALSE(validationFlag(figures(0.147, 8.8, 0.072, 4.1)));
  // 0.147 x 1.1 + 0.002 = 0.1637 m and 8.8 x 1.1 + 0.05 = 9.73 deg are the limits.
  EXPECT_FALSE(validationFlag(figures(0.147, 8.8, 0.163, 9.7)));
  // Both tiny (a nominal that is already right): the floors keep noise from being a verdict.
  EXPECT_FALSE(validationFlag(figures(0.0010, 0.010, 0.0025, 0.04)));
}

TEST(ValidationFlag, WorseTranslationIsFlaggedWithItsRatio) {
  const auto flag = validationFlag(figures(0.142, 8.8, 0.200, 8.0));
  ASSERT_TRUE(flag);
  EXPECT_EQ(flag->param, "held_out");
  EXPECT_NEAR(flag->ratio, 0.200 / 0.142, 1e-12);
  EXPECT_NE(flag->likely_cause.find("held-out 30 %"), std::string::npos) << flag->likely_cause;
  EXPECT_NE(flag->likely_cause.find("0.200 vs 0.142 m"), std::string::npos);
}

TEST(ValidationFlag, WorseRotationAloneIsFlaggedWithTheRotationRatio) {
  // The TurtleBot4 recording: translation better (0.072 -> 0.044 m), rotation 0.35 -> 0.78 deg.
  const auto flag = validationFlag(figures(0.072, 0.35, 0.044, 0.78));
  ASSERT_TRUE(flag);
  EXPECT_NEAR(flag->ratio, 0.78 / 0.35, 1e-12);
}

// A Neato recording (square_drive_bag_2): the calibrated mount 165 mm off the tf's to the side,
// the wheels fine with the dataset's mount: the cause names the mount, not the wheels.
TEST(ValidationFlag, AMountThatAloneIsWorseIsNamedAsTheCause) {
  ValidationFigures v = figures(0.054, 1.90, 0.264, 1.95);
  v.calibrated_wheels = HeldOutError{0.053, 1.95};
  const auto flag = validationFlag(v);
  ASSERT_TRUE(flag);
  EXPECT_NEAR(flag->ratio, 0.264 / 0.054, 1e-12);
  EXPECT_NE(flag->likely_cause.find("lidar mount"), std::string::npos) << flag->likely_cause;
  EXPECT_NE(flag->likely_cause.find("(0.053 m, 1.95 deg)"), std::string::npos);
  // The wheels worse too: the geometry is the cause, as without the figure.
  v.calibrated_wheels = HeldOutError{0.200, 1.95};
  EXPECT_EQ(validationFlag(v)->likely_cause.find("lidar mount"), std::string::npos);
  EXPECT_NE(validationFlag(v)->likely_cause.find("geometry"), std::string::npos);
}

// AriB2003's wall follower: the calibration within its sigmas of the nominal (chi2 1.0 over 3),
// held out worse than raw: the cause says the calibration never showed the nominal wrong.
TEST(ValidationFlag, ACalibrationThatNeverShowedTheNominalWrongSaysSo) {
  const ValidationFigures v = figures(0.050, 2.38, 0.066, 4.52);
  NominalTest close;
  close.chi2 = 1.0;
  close.p = chi2Survival3(1.0);
  const auto flag = validationFlag(v, {}, close);
  ASSERT_TRUE(flag);
  EXPECT_NE(flag->likely_cause.find("did not show the nominal geometry wrong (chi2 1.0 over 3, p "
                                    "0.80)"),
            std::string::npos)
      << flag->likely_cause;
  NominalTest far = close;
  far.chi2 = 24.9;
  far.p = chi2Survival3(24.9);
  far.shows_nominal_wrong = true;  // then the drive did not pin it down, as without the test
  EXPECT_EQ(validationFlag(v, {}, far)->likely_cause, validationFlag(v)->likely_cause);
}

}  // namespace
}  // namespace slamprep::algo
