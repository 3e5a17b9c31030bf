// Asymmetric whiskers (y_err_low): the suite figures draw min..max over seeds on log axes,
// where a ±1σ bar would cross zero and run off the axis.
#include <gtest/gtest.h>

#include "slamprep/core/error.hpp"
#include "slamprep/eval/plot/plot.hpp"

namespace slamprep::eval::plot {
namespace {

TEST(Whiskers, AsymmetricWhiskersSetTheAxisRangeOnALogAxis) {
  // mean 10, min 2, max 50: both ends inside the range, which is not decades wider.
  Axes axes{.log_y = true, .categories = {"a"}};
  axes.series.push_back(
      {.x = {0}, .y = {10}, .y_err = {40}, .y_err_low = {8}, .style = Style::Markers});
  const PanelLayout L = layoutFigure(Figure{.axes = {axes}}).front();
  EXPECT_LT(L.y.min, 2.0);
  EXPECT_GT(L.y.min, 1.0);
  EXPECT_GT(L.y.max, 50.0);
  EXPECT_LT(L.y.max, 100.0);
}

TEST(Whiskers, MismatchedLowWhiskersAreRefused) {
  Axes axes;
  axes.series.push_back({.x = {0, 1}, .y = {1, 2}, .y_err = {1, 1}, .y_err_low = {1}});
  EXPECT_THROW(layoutFigure(Figure{.axes = {axes}}), InputError);
}

}  // namespace
}  // namespace slamprep::eval::plot
