// Held-out validation as a verdict (algo/calibration/validation_flag.hpp): a calibrated geometry
// that predicts the held-out part worse than the nominal one is flagged, beyond 10 % + a floor.
#include "algo/calibration/validation_flag.hpp"

#include <gtest/gtest.h>

namespace slamprep::algo {
namespace {

ValidationFigures figures(double raw_m, double raw_deg, double cal_m, double cal_deg) {
  return ValidationFigures{0.3, {raw_m, raw_deg}, {cal_m, cal_deg}};
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

}  // namespace
}  // namespace slamprep::algo
