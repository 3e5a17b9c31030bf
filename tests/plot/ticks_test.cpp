#include "slamprep/eval/plot/ticks.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <iomanip>
#include <random>

namespace slamprep::eval::plot {
namespace {

const std::string kMinus = "\xE2\x88\x92";

std::vector<double> majorValues(const std::vector<Tick>& ticks) {
  std::vector<double> values;
  for (const Tick& t : ticks) {
    if (t.major) values.push_back(t.value);
  }
  return values;
}

TEST(NiceStep, RoundsUpToOneTwoFive) {
  EXPECT_DOUBLE_EQ(niceStep(0.3), 0.5);
  EXPECT_DOUBLE_EQ(niceStep(1.0), 1.0);
  EXPECT_DOUBLE_EQ(niceStep(1.01), 2.0);
  EXPECT_DOUBLE_EQ(niceStep(2.5), 5.0);
  EXPECT_DOUBLE_EQ(niceStep(7.0), 10.0);
  EXPECT_DOUBLE_EQ(niceStep(0.013), 0.02);
  EXPECT_DOUBLE_EQ(niceStep(3e7), 5e7);
}

TEST(FormatTick, CompactAndExact) {
  EXPECT_EQ(formatTick(0.30000000000000004, 0.1, false), "0.3");
  EXPECT_EQ(formatTick(2.0, 0.5, false), "2.0");
  EXPECT_EQ(formatTick(-1.5, 0.5, false), kMinus + "1.5");
  EXPECT_EQ(formatTick(-1e-17, 0.2, false), "0.0");  // never "-0.0"
  EXPECT_EQ(formatTick(40.0, 20.0, false), "40");
  EXPECT_EQ(formatTick(1e-4, 1e-4, true), "1e" + kMinus + "4");
  EXPECT_EQ(formatTick(2.5e-5, 5e-6, true), "2.5e" + kMinus + "5");
  EXPECT_EQ(formatTick(150000.0, 50000.0, true), "1.5e5");
  EXPECT_EQ(formatTick(-3e6, 1e6, true), kMinus + "3e6");
  EXPECT_EQ(formatTick(0.0, 1e-4, true), "0");
}

TEST(FormatTick, ScientificOnlyForExtremeMagnitudes) {
  EXPECT_FALSE(wantsScientific({0.0, 1.0}));
  EXPECT_FALSE(wantsScientific({0.0, 0.005}));
  EXPECT_TRUE(wantsScientific({0.0, 0.0005}));
  EXPECT_TRUE(wantsScientific({-2e5, 1.0}));
  EXPECT_FALSE(wantsScientific({-99999.0, 1.0}));
}

TEST(LinearTicks, UnitRange) {
  const auto ticks = linearTicks({0.0, 1.0}, 6);
  ASSERT_EQ(ticks.size(), 6u);
  for (int i = 0; i < 6; ++i) {
    EXPECT_NEAR(ticks[i].value, 0.2 * i, 1e-12);
    EXPECT_TRUE(ticks[i].major);
  }
  EXPECT_EQ(ticks[0].label, "0.0");
  EXPECT_EQ(ticks[3].label, "0.6");
}

TEST(LinearTicks, NegativeLabelsUseMinusSign) {
  // Span 15.9 / 5 -> step 5 gives {0, 5, 10}; step 2 would give 8 ticks (> 5).
  const std::vector<double> expected{0.0, 5.0, 10.0};
  EXPECT_EQ(majorValues(linearTicks({-3.7, 12.2}, 5)), expected);
  const auto wide = linearTicks({-3.7, 12.2}, 9);  // step 2: -2 ... 12
  EXPECT_EQ(wide.front().label, kMinus + "2");
}

// Property over many ranges (fixed seed): ticks are inside the range, evenly spaced by a 1-2-5
// step, and there are between 2 and max_major of them (more only when 2 need a finer step).
TEST(LinearTicks, PropertiesOverRandomRanges) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> exponent(-8.0, 8.0), unit(-1.0, 1.0);
  for (int trial = 0; trial < 2000; ++trial) {
    const double scale = std::pow(10.0, exponent(rng));
    double a = unit(rng) * scale, b = unit(rng) * scale;
    if (a == b) continue;
    if (a > b) std::swap(a, b);
    const int max_major = 3 + trial % 7;
    const auto values = majorValues(linearTicks({a, b}, max_major));
    ASSERT_GE(values.size(), 2u) << a << " " << b;
    const double step = values[1] - values[0];
    if (values.size() > static_cast<std::size_t>(max_major)) {
      // Allowed only when the next coarser 1-2-5 step would leave fewer than two ticks.
      const double coarser = niceStep(step * 1.5);
      const double inside = std::floor(b / coarser + 1e-9) - std::ceil(a / coarser - 1e-9) + 1;
      EXPECT_LT(inside, 2.0) << std::setprecision(17) << a << " " << b;
    }
    const double mantissa = step / std::pow(10.0, std::floor(std::log10(step) + 1e-9));
    EXPECT_TRUE(std::abs(mantissa - 1) < 1e-6 || std::abs(mantissa - 2) < 1e-6 ||
                std::abs(mantissa - 5) < 1e-6)
        << step;
    for (std::size_t i = 0; i < values.size(); ++i) {
      const double slack = 1e-9 * (b - a);
      EXPECT_GE(values[i], a - slack);
      EXPECT_LE(values[i], b + slack);
      if (i > 0) {
        EXPECT_NEAR(values[i] - values[i - 1], step, 1e-6 * step);
      }
    }
  }
}

TEST(LogTicks, DecadesWithMinorTicks) {
  const auto ticks = logTicks({1e-5, 1e-1}, 8);
  const std::vector<double> majors = majorValues(ticks);
  ASSERT_EQ(majors.size(), 5u);
  for (int k = 0; k < 5; ++k) EXPECT_NEAR(std::log10(majors[k]), -5 + k, 1e-12);
  EXPECT_EQ(ticks.front().label, "10^{" + kMinus + "5}");
  // 2..9 x 10^k inside each of the four decades.
  EXPECT_EQ(ticks.size() - majors.size(), 4u * 8u);
}

TEST(LogTicks, ManyDecadesThinOut) {
  const auto ticks = logTicks({1e-12, 1e12}, 6);
  const std::vector<double> majors = majorValues(ticks);
  // 25 decades, at most 6 labels: every 5th decade, i.e. 1e-10, 1e-5, 1, 1e5, 1e10.
  ASSERT_EQ(majors.size(), 5u);
  EXPECT_NEAR(std::log10(majors[0]), -10.0, 1e-12);
  EXPECT_NEAR(std::log10(majors[2]), 0.0, 1e-12);
  EXPECT_EQ(ticks.size(), 25u);  // the other decades stay as minor ticks
}

TEST(LogTicks, NarrowRangeLabelsOneTwoFive) {
  const auto ticks = logTicks({0.3, 4.0}, 8);
  const std::vector<double> majors = majorValues(ticks);
  ASSERT_EQ(majors.size(), 3u);
  EXPECT_DOUBLE_EQ(majors[0], 0.5);
  EXPECT_DOUBLE_EQ(majors[1], 1.0);
  EXPECT_DOUBLE_EQ(majors[2], 2.0);
  for (const Tick& t : ticks) {
    if (t.value == 0.5) {
      EXPECT_EQ(t.label, "0.5");
    } else if (t.value == 2.0) {
      EXPECT_EQ(t.label, "2");
    }
  }
}

TEST(LogTicks, TwoDecadesGetOneTwoFiveLabelsWhenTheyFit) {
  const auto ticks = logTicks({0.9, 11.0}, 6);
  const std::vector<double> expected{1.0, 2.0, 5.0, 10.0};
  EXPECT_EQ(majorValues(ticks), expected);
  EXPECT_EQ(ticks.back().label, "10");  // one label style on the axis: plain numbers
  // Six 1-2-5 values (5e-5 ... 2e-3) do not fit in four labels: decades only.
  const std::vector<double> decades = majorValues(logTicks({2e-5, 3e-3}, 4));
  ASSERT_EQ(decades.size(), 2u);
  EXPECT_NEAR(std::log10(decades[0]), -4.0, 1e-12);
  EXPECT_NEAR(std::log10(decades[1]), -3.0, 1e-12);
}

TEST(LogTicks, ADecadeAndABitGetsSparseMantissasNotLinearSteps) {
  // 0.006 .. 0.095 with room for two labels: 1-2-5 gives three (0.01, 0.02, 0.05); linear steps
  // (0.02, 0.04, ...) would bunch at the top of a log axis and leave its bottom bare.
  const std::vector<double> majors = majorValues(logTicks({0.006, 0.095}, 2));
  ASSERT_EQ(majors.size(), 2u);
  EXPECT_NEAR(majors[0], 0.01, 1e-15);
  EXPECT_NEAR(majors[1], 0.03, 1e-15);
}

TEST(LogTicks, VeryNarrowRangeFallsBackToLinear) {
  const auto majors = majorValues(logTicks({1.1, 1.9}, 6));
  ASSERT_GE(majors.size(), 2u);
  EXPECT_NEAR(majors[1] - majors[0], 0.2, 1e-12);  // linear 1-2-5 step inside [1.1, 1.9]
}

}  // namespace
}  // namespace slamprep::eval::plot
