// Automatic ranges of log axes: never narrower than a decade, so that the distance between two
// points says how many times one is the other.
#include <gtest/gtest.h>

#include <cmath>

#include "slamprep/eval/plot/plot.hpp"

namespace slamprep::eval::plot {
namespace {

PanelLayout layoutOf(std::vector<double> y) {
  Axes axes{.log_y = true, .categories = {"a", "b"}};
  axes.series.push_back({.x = {0, 1}, .y = std::move(y), .style = Style::Markers});
  return layoutFigure(Figure{.axes = {axes}}).front();
}

TEST(LogAxis, ANarrowSpreadGetsOneDecadeCentredOnIt) {
  // 0.0255 and 0.0262 differ by 3 %: a range fitted to them would show them an axis apart.
  const PanelLayout L = layoutOf({0.0255, 0.0262});
  EXPECT_NEAR(std::log10(L.y.max / L.y.min), 1.0, 1e-12);
  const double centre = std::sqrt(L.y.min * L.y.max);
  EXPECT_GT(centre, 0.0255);
  EXPECT_LT(centre, 0.0262);
}

TEST(LogAxis, ASpreadOverADecadeKeepsItsMargins) {
  const PanelLayout L = layoutOf({0.01, 1.0});
  EXPECT_LT(L.y.min, 0.01);
  EXPECT_GT(L.y.max, 1.0);
  EXPECT_LT(std::log10(L.y.max / L.y.min), 2.5);
}

}  // namespace
}  // namespace slamprep::eval::plot
