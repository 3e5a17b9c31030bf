// Box plots (Style::Box): the suite figures draw the signed error of many seeds as quartiles,
// median and Tukey whiskers, where min..max whiskers would only show the two rarest seeds.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "slamprep/core/error.hpp"
#include "slamprep/eval/plot/plot.hpp"

namespace slamprep::eval::plot {
namespace {

using Rgba = std::array<std::uint8_t, 4>;

// 1..9 and 19: quartiles at sorted positions 2.25, 4.5 and 6.75 (type 7, numpy's default);
// IQR 4.5 puts the upper fence at 7.75 + 6.75 = 14.5, so 19 is an outlier and 9 the whisker.
const std::vector<double> kSample = {19, 1, 2, 3, 4, 5, 6, 7, 8, 9};

TEST(BoxStats, QuartilesWhiskersAndOutliersOfAKnownSample) {
  std::vector<double> sample = kSample;
  sample.push_back(std::numeric_limits<double>::quiet_NaN());  // not a value: left out
  const BoxStats b = boxStats(sample);
  EXPECT_EQ(b.n, 10u);
  EXPECT_DOUBLE_EQ(b.q1, 3.25);
  EXPECT_DOUBLE_EQ(b.median, 5.5);
  EXPECT_DOUBLE_EQ(b.q3, 7.75);
  EXPECT_DOUBLE_EQ(b.whisker_low, 1.0);  // the lower fence is -3.5: nothing beyond it
  EXPECT_DOUBLE_EQ(b.whisker_high, 9.0);
  EXPECT_EQ(b.outliers, std::vector<double>{19.0});
}

TEST(BoxStats, OddSampleHasItsMiddleValueAsMedianAndEmptyHasNone) {
  const BoxStats b = boxStats({-3, 5, 1, -1, 2});  // sorted -3 -1 1 2 5
  EXPECT_DOUBLE_EQ(b.median, 1.0);
  EXPECT_DOUBLE_EQ(b.q1, -1.0);
  EXPECT_DOUBLE_EQ(b.q3, 2.0);
  EXPECT_DOUBLE_EQ(b.whisker_low, -3.0);
  EXPECT_DOUBLE_EQ(b.whisker_high, 5.0);
  EXPECT_TRUE(b.outliers.empty());
  EXPECT_EQ(boxStats({}).n, 0u);
}

class BoxRender : public ::testing::Test {
 protected:
  void SetUp() override {
    Axes axes{.y_range = Range{0, 20}, .grid = false, .legend = LegendPosition::None};
    axes.categories = {"a"};
    Series s{.style = Style::Box, .color = Color{0, 0, 1, 1}};
    for (const double v : kSample) s.x.push_back(0.0), s.y.push_back(v);
    axes.series.push_back(s);
    figure_ = Figure{.width_px = 400, .height_px = 300, .axes = {axes}};
    layout_ = layoutFigure(figure_).at(0);
    image_ = render(figure_);
  }
  // The pixel at data (x, y).
  Rgba at(double x, double y) const {
    return image_.pixel(static_cast<int>(std::floor(layout_.toPixelX(x))),
                        static_cast<int>(std::floor(layout_.toPixelY(y))));
  }
  Figure figure_;
  PanelLayout layout_;
  Image image_;
};

TEST_F(BoxRender, BoxMedianWhiskersAndOutlierLandWhereTheStatisticsSay) {
  // One series in one category: a box 0.72 wide (90 % of 80 % of the slot) centred on x = 0.
  const Rgba median = at(0.2, 5.5);
  EXPECT_LT(median[0] + median[1] + median[2], 3 * 80) << "dark median line";
  const Rgba inside = at(0.2, 4.4);  // between q1 and the median: 30 % blue over white
  EXPECT_NEAR(inside[0], 178, 6);
  EXPECT_EQ(inside[2], 255);
  EXPECT_EQ(at(0.45, 4.4), (Rgba{255, 255, 255, 255})) << "beyond the box's side";
  EXPECT_LT(at(0.0, 8.5)[1], 90) << "upper whisker, 7.75 to 9";
  EXPECT_LT(at(0.0, 2.0)[1], 90) << "lower whisker, 1 to 3.25";
  EXPECT_EQ(at(0.0, 11.0), (Rgba{255, 255, 255, 255})) << "between whisker and outlier";
  EXPECT_EQ(at(0.0, 0.5), (Rgba{255, 255, 255, 255})) << "below the lower whisker";
  EXPECT_LT(at(0.0, 19.0)[1], 120) << "the outlier's dot";
  EXPECT_EQ(at(0.2, 8.5), (Rgba{255, 255, 255, 255})) << "beside the whisker";
}

TEST(BoxLayout, AutoRangeHoldsEveryValueAndTwoSeriesStandSideBySide) {
  Axes axes{.grid = false, .legend = LegendPosition::None, .categories = {"a"}};
  Series s{.style = Style::Box};
  for (const double v : kSample) s.x.push_back(0.0), s.y.push_back(-v);
  axes.series = {s, s};
  axes.series[0].color = Color{1, 0, 0, 1};
  axes.series[1].color = Color{0, 0, 1, 1};
  const Figure figure{.width_px = 400, .height_px = 300, .axes = {axes}};
  const PanelLayout L = layoutFigure(figure).at(0);
  EXPECT_LT(L.y.min, -19.0);  // the outlier is drawn, so it is in range
  EXPECT_GT(L.y.max, -1.0);
  EXPECT_LT(L.y.max, 0.0);
  // Slots of 0.4 (80 % of the category over two series): boxes centred at -0.2 and +0.2.
  const Image image = render(figure);
  const auto at = [&](double x, double y) {
    return image.pixel(static_cast<int>(L.toPixelX(x)), static_cast<int>(L.toPixelY(y)));
  };
  EXPECT_EQ(at(-0.3, -4.4)[0], 255) << "red box on the left";
  EXPECT_LT(at(-0.3, -4.4)[2], 200);
  EXPECT_EQ(at(0.3, -4.4)[2], 255) << "blue box on the right";
  EXPECT_LT(at(0.3, -4.4)[0], 200);
  EXPECT_EQ(at(0.0, -4.4), (Rgba{255, 255, 255, 255})) << "a gap between them";
}

TEST(BoxLayout, ErrorBarsOnABoxAreRefused) {
  Axes axes;
  axes.series.push_back({.x = {0}, .y = {1}, .y_err = {1}, .style = Style::Box});
  EXPECT_THROW(layoutFigure(Figure{.axes = {axes}}), InputError);
}

}  // namespace
}  // namespace slamprep::eval::plot
