#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>
#include <thread>

#include "sample_figures.hpp"
#include "slamprep/core/error.hpp"
#include "slamprep/eval/plot/gl_canvas.hpp"
#include "slamprep/eval/plot/plot.hpp"

namespace slamprep::eval::plot {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
const Color kRed{1, 0, 0, 1};
const Color kBlue{0, 0, 1, 1};

using Rgba = std::array<std::uint8_t, 4>;

/// A plain 400x300 figure with one panel, no grid, no legend.
Figure plain(Axes axes) {
  axes.grid = false;
  axes.legend = LegendPosition::None;
  return Figure{.width_px = 400, .height_px = 300, .axes = {axes}};
}

void expectColor(const Rgba& p, int r, int g, int b, int tolerance, const std::string& where) {
  EXPECT_NEAR(p[0], r, tolerance) << where;
  EXPECT_NEAR(p[1], g, tolerance) << where;
  EXPECT_NEAR(p[2], b, tolerance) << where;
}

int countPixels(const Image& image, int x0, int y0, int x1, int y1, auto predicate) {
  int count = 0;
  for (int y = std::max(0, y0); y < std::min(image.height, y1); ++y) {
    for (int x = std::max(0, x0); x < std::min(image.width, x1); ++x)
      count += predicate(image.pixel(x, y));
  }
  return count;
}

bool isDark(const Rgba& p) {
  return p[0] < 128 && p[1] < 128 && p[2] < 128;
}

// A 3 px stroke centred on row y_c covers [y_c - 1.5, y_c + 1.5], so pixel row floor(y_c) is
// always fully inside (exact colour) and rows floor(y_c) +- 3 are always fully outside (white).
TEST(Render, HorizontalLineLandsOnTheComputedRow) {
  Axes axes{.x_range = Range{0, 1}, .y_range = Range{0, 1}};
  axes.series.push_back({.x = {0, 1}, .y = {0.5, 0.5}, .color = kRed, .line_width_px = 3.0});
  const Figure figure = plain(axes);
  const PanelLayout L = layoutFigure(figure).at(0);
  const double y_c = L.toPixelY(0.5);
  EXPECT_DOUBLE_EQ(y_c, (L.top_px + L.bottom_px) / 2);
  const Image image = render(figure);
  const int row = static_cast<int>(std::floor(y_c));
  for (const double f : {0.1, 0.5, 0.9}) {
    const int col = static_cast<int>(L.left_px + f * (L.right_px - L.left_px));
    expectColor(image.pixel(col, row), 255, 0, 0, 0, "on the line");
    expectColor(image.pixel(col, row - 3), 255, 255, 255, 0, "above");
    expectColor(image.pixel(col, row + 3), 255, 255, 255, 0, "below");
  }
}

TEST(Render, VerticalLineLandsOnTheComputedColumn) {
  Axes axes{.x_range = Range{-2, 2}, .y_range = Range{0, 1}};
  axes.series.push_back({.x = {-1, -1}, .y = {0, 1}, .color = kBlue, .line_width_px = 3.0});
  const Figure figure = plain(axes);
  const PanelLayout L = layoutFigure(figure).at(0);
  const double x_c = L.toPixelX(-1.0);
  EXPECT_NEAR(x_c, L.left_px + 0.25 * (L.right_px - L.left_px), 1e-9);
  const Image image = render(figure);
  const int col = static_cast<int>(std::floor(x_c));
  const int row = static_cast<int>((L.top_px + L.bottom_px) / 2);
  expectColor(image.pixel(col, row), 0, 0, 255, 0, "on the line");
  expectColor(image.pixel(col - 3, row), 255, 255, 255, 0, "left");
  expectColor(image.pixel(col + 3, row), 255, 255, 255, 0, "right");
}

TEST(Render, LogScalePutsDecadesEquallyApart) {
  Axes axes{.log_y = true, .x_range = Range{0, 1}, .y_range = Range{1, 1e4}};
  axes.series.push_back({.x = {0, 1}, .y = {10, 10}, .color = kRed, .line_width_px = 3.0});
  axes.series.push_back({.x = {0, 1}, .y = {1000, 1000}, .color = kBlue, .line_width_px = 3.0});
  Figure figure = plain(axes);
  figure.axes[0].grid = true;
  const PanelLayout L = layoutFigure(figure).at(0);
  const double decade = (L.bottom_px - L.top_px) / 4;
  for (int k = 0; k <= 4; ++k)
    EXPECT_NEAR(L.toPixelY(std::pow(10.0, k)), L.bottom_px - k * decade, 1e-9);
  EXPECT_NEAR(L.toPixelY(std::sqrt(10.0)), L.bottom_px - decade / 2, 1e-9);

  const Image image = render(figure);
  const int col = static_cast<int>((L.left_px + L.right_px) / 2);
  expectColor(image.pixel(col, static_cast<int>(std::floor(L.toPixelY(10)))), 255, 0, 0, 0, "10");
  expectColor(image.pixel(col, static_cast<int>(std::floor(L.toPixelY(1000)))), 0, 0, 255, 0,
              "1e3");
  // The major grid line at 100 sits on the pixel row containing its position: grey 0.88 * 255.
  const Rgba grid = image.pixel(col, static_cast<int>(std::floor(L.toPixelY(100))));
  expectColor(grid, 224, 224, 224, 1, "grid at 100");
}

TEST(Render, TitleAndLabelsProduceInk) {
  Axes axes{.x_label = "x [m]", .y_label = "y [m]", .x_range = Range{0, 1}, .y_range = Range{0, 1}};
  Figure with_title = plain(axes);
  with_title.title = "A title";
  Figure without_title = plain(axes);
  without_title.title = " ";  // same layout, no glyphs
  const PanelLayout L = layoutFigure(with_title).at(0);
  const Image a = render(with_title), b = render(without_title);
  const int band = static_cast<int>(L.top_px) - 8;  // above the plot and its top tick label
  ASSERT_GT(band, 10);
  EXPECT_GT(countPixels(a, 0, 0, a.width, band, isDark), 50);
  EXPECT_EQ(countPixels(b, 0, 0, b.width, band, isDark), 0);
  // The title is centred: as much ink left of the middle as right of it, within a glyph.
  const int left = countPixels(a, 0, 0, a.width / 2, band, isDark);
  const int right = countPixels(a, a.width / 2, 0, a.width, band, isDark);
  EXPECT_NEAR(left, right, 0.35 * (left + right));
  // x label below the tick labels, y label left of them.
  EXPECT_GT(countPixels(a, 0, static_cast<int>(L.bottom_px) + 30, a.width, a.height, isDark), 20);
  EXPECT_GT(countPixels(a, 0, 0, 25, a.height, isDark), 20);
}

TEST(Render, SameFigureSameBytes) {
  const Figure figure{.width_px = 600, .height_px = 400, .axes = {samples::deskewAxes()}};
  const Image a = render(figure), b = render(figure);
  EXPECT_EQ(a.rgba, b.rgba);
  const auto dir = std::filesystem::path(SLAMPREP_BINARY_DIR) / "test_scratch" / "plot";
  std::filesystem::create_directories(dir);
  renderPng(figure, dir / "same_a.png");
  renderPng(figure, dir / "same_b.png");
  auto bytes = [](const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  };
  EXPECT_EQ(bytes(dir / "same_a.png"), bytes(dir / "same_b.png"));
}

TEST(Render, NonFiniteAndDegenerateDataDoNotCrash) {
  Axes axes{.log_x = true, .log_y = true};
  axes.series.push_back({.label = "holes",
                         .x = {1, 2, kNaN, 4, 5, kInf, -1, 8},
                         .y = {1, kNaN, 3, 4, -kInf, 6, 7, 0},
                         .y_err = {0.1, 0.2, kNaN, 10.0, 0.1, kInf, 0.1, 0.1},
                         .style = Style::LineMarkers});
  axes.series.push_back({.label = "empty"});
  axes.series.push_back({.label = "all NaN", .x = {kNaN, kNaN}, .y = {kNaN, kNaN}});
  Axes flat;
  flat.series.push_back({.label = "flat", .x = {3, 3, 3}, .y = {5, 5, 5}, .style = Style::Markers});
  Axes nothing;
  Axes bars{.categories = {"a", "b"}};
  bars.series.push_back({.x = {0, 1}, .y = {kNaN, kInf}, .y_err = {1, 1}, .style = Style::Bars});
  const Figure figure{
      .width_px = 500, .height_px = 400, .rows = 2, .cols = 2, .axes = {axes, flat, nothing, bars}};
  const auto layouts = layoutFigure(figure);
  for (const PanelLayout& L : layouts) {
    EXPECT_TRUE(std::isfinite(L.x.min) && std::isfinite(L.x.max) && L.x.min < L.x.max);
    EXPECT_TRUE(std::isfinite(L.y.min) && std::isfinite(L.y.max) && L.y.min < L.y.max);
  }
  // Usable points of "holes": x in {1, 4, 8?} ... (1,1) (4,4) only; plus error bar 4 +- 10
  // whose upper end 14 counts and whose lower end -6 is unusable on a log axis.
  EXPECT_LT(layouts[0].y.min, 1.0);
  EXPECT_GT(layouts[0].y.max, 14.0);
  EXPECT_LT(layouts[0].y.max, 20.0);
  // All-equal values get +-10 % around them; no data at all gets [0, 1].
  EXPECT_NEAR(layouts[1].y.min, 4.5, 1e-12);
  EXPECT_NEAR(layouts[1].y.max, 5.5, 1e-12);
  EXPECT_NEAR(layouts[1].x.min, 2.7, 1e-12);
  EXPECT_EQ(layouts[2].x.min, 0.0);
  EXPECT_EQ(layouts[2].y.max, 1.0);
  Image image;
  ASSERT_NO_THROW(image = render(figure));
  EXPECT_EQ(image.width, 500);
  EXPECT_EQ(image.height, 400);
}

TEST(Render, InvalidFiguresThrowInputErrorsNamingTheField) {
  auto message = [](const Figure& f) -> std::string {
    try {
      render(f);
    } catch (const InputError& e) {
      return e.what();
    }
    return "no error";
  };
  Axes mismatched;
  mismatched.series.push_back({.label = "m", .x = {1, 2}, .y = {1}});
  EXPECT_NE(message(Figure{.axes = {mismatched}}).find("axes[0].series[0] \"m\""),
            std::string::npos);
  Axes bad_err;
  bad_err.series.push_back({.x = {1, 2}, .y = {1, 2}, .y_err = {1}});
  EXPECT_NE(message(Figure{.axes = {bad_err}}).find("y_err"), std::string::npos);
  EXPECT_NE(message(Figure{.axes = {Axes{.y_range = Range{1, 1}}}}).find("y_range"),
            std::string::npos);
  EXPECT_NE(message(Figure{.axes = {Axes{.log_x = true, .x_range = Range{0, 1}}}}).find("x_range"),
            std::string::npos);
  EXPECT_NE(message(Figure{.axes = {Axes{}, Axes{}}}).find("grid"), std::string::npos);
  EXPECT_NE(message(Figure{.width_px = 0}).find("size"), std::string::npos);
  EXPECT_NE(message(Figure{.font_path = "/nonexistent.ttf"}).find("/nonexistent.ttf"),
            std::string::npos);
}

TEST(Render, EqualAspectGivesSquarePixels) {
  Axes axes{.equal_aspect = true};
  axes.series.push_back({.x = {0, 10}, .y = {0, 1}});
  const PanelLayout L = layoutFigure(plain(axes)).at(0);
  const double x_per_px = (L.x.max - L.x.min) / (L.right_px - L.left_px);
  const double y_per_px = (L.y.max - L.y.min) / (L.bottom_px - L.top_px);
  EXPECT_NEAR(x_per_px, y_per_px, 1e-12 * x_per_px);
  EXPECT_LE(L.x.min, 0.0);
  EXPECT_GE(L.x.max, 10.0);
  EXPECT_NEAR((L.y.min + L.y.max) / 2, 0.5, 1e-12);  // widened about the data centre
}

TEST(Render, AutoLegendAvoidsTheData) {
  Axes axes{.x_range = Range{0, 1}, .y_range = Range{0, 1}};
  Series crowd{.label = "data", .style = Style::Markers};
  for (int i = 0; i < 10; ++i) {
    for (int j = 0; j < 10; ++j)
      crowd.x.push_back(0.55 + 0.045 * i), crowd.y.push_back(0.55 + 0.045 * j);
  }
  axes.series.push_back(crowd);
  Figure figure = plain(axes);
  figure.axes[0].legend = LegendPosition::Auto;
  const PanelLayout L = layoutFigure(figure).at(0);
  const Image image = render(figure);
  auto border = [](const Rgba& p) { return p[0] == 204 && p[1] == 204 && p[2] == 204; };
  const int mid_x = static_cast<int>((L.left_px + L.right_px) / 2);
  const int mid_y = static_cast<int>((L.top_px + L.bottom_px) / 2);
  // Upper right holds the data; the first free corner in matplotlib's order is upper left.
  EXPECT_GT(countPixels(image, static_cast<int>(L.left_px), static_cast<int>(L.top_px), mid_x,
                        mid_y, border),
            50);
  EXPECT_EQ(countPixels(image, mid_x, static_cast<int>(L.top_px), static_cast<int>(L.right_px),
                        mid_y, border),
            0);
}

TEST(Render, BarsStandOnZeroAtTheirCategory) {
  Axes axes{.categories = {"a", "b"}};
  axes.series.push_back({.x = {0, 1}, .y = {2, 4}, .style = Style::Bars, .color = kBlue});
  const Figure figure = plain(axes);
  const PanelLayout L = layoutFigure(figure).at(0);
  EXPECT_EQ(L.y.min, 0.0);  // no margin below bars that start at 0
  EXPECT_NEAR(L.x.min, -0.5, 1e-12);
  const Image image = render(figure);
  auto at = [&](double x, double y) {
    return image.pixel(static_cast<int>(L.toPixelX(x)), static_cast<int>(L.toPixelY(y)));
  };
  expectColor(at(1.0, 2.0), 0, 0, 255, 0, "inside bar b");
  expectColor(at(0.0, 1.0), 0, 0, 255, 0, "inside bar a");
  expectColor(at(0.0, 3.0), 255, 255, 255, 0, "above bar a");
  expectColor(at(0.5, 1.0), 255, 255, 255, 0, "between the bars");
}

TEST(Render, ErrorBarsSpanOneSigma) {
  Axes axes{.x_range = Range{0, 2}, .y_range = Range{0, 2}};
  axes.series.push_back(
      {.x = {1}, .y = {1}, .y_err = {0.5}, .style = Style::Markers, .color = kRed});
  const Figure figure = plain(axes);
  const PanelLayout L = layoutFigure(figure).at(0);
  const Image image = render(figure);
  const int col = static_cast<int>(std::floor(L.toPixelX(1.0)));
  // The bar is 1.5 px wide (0.75 x the 2 px line width) centred on the column's position; the
  // column containing it is at least 3/4 covered.
  EXPECT_LT(image.pixel(col, static_cast<int>(L.toPixelY(1.4)))[1], 70) << "inside +1 sigma";
  EXPECT_LT(image.pixel(col, static_cast<int>(L.toPixelY(0.6)))[1], 70) << "inside -1 sigma";
  expectColor(image.pixel(col, static_cast<int>(L.toPixelY(1.6))), 255, 255, 255, 0, "beyond");
  expectColor(image.pixel(col, static_cast<int>(L.toPixelY(0.4))), 255, 255, 255, 0, "beyond");
}

TEST(Render, NoInkTouchesTheImageBorder) {
  // Labels must never be clipped: the outermost two pixels stay white in every sample figure.
  for (const Axes& axes :
       {samples::deskewAxes(), samples::calibrationAxes(Style::Bars), samples::trajectoryAxes(),
        samples::scanAxes(), samples::errorVsTimeAxes()}) {
    const Image image =
        render(Figure{.width_px = 800, .height_px = 500, .title = "T", .axes = {axes}});
    auto non_white = [](const Rgba& p) { return p[0] < 250 || p[1] < 250 || p[2] < 250; };
    const int w = image.width, h = image.height;
    EXPECT_EQ(countPixels(image, 0, 0, w, 2, non_white), 0) << axes.title;
    EXPECT_EQ(countPixels(image, 0, h - 2, w, h, non_white), 0) << axes.title;
    EXPECT_EQ(countPixels(image, 0, 0, 2, h, non_white), 0) << axes.title;
    EXPECT_EQ(countPixels(image, w - 2, 0, w, h, non_white), 0) << axes.title;
  }
}

TEST(Render, PanelsStayInsideTheirCells) {
  const Figure figure{
      .width_px = 1000,
      .height_px = 700,
      .title = "grid",
      .rows = 2,
      .cols = 2,
      .axes = {samples::deskewAxes(), samples::trajectoryAxes(), samples::scanAxes()}};
  const auto layouts = layoutFigure(figure);
  ASSERT_EQ(layouts.size(), 3u);
  EXPECT_LT(layouts[0].right_px, layouts[1].left_px);
  EXPECT_LT(layouts[0].bottom_px, layouts[2].top_px);
  for (const PanelLayout& L : layouts) {
    EXPECT_GT(L.right_px - L.left_px, 300);
    EXPECT_GT(L.bottom_px - L.top_px, 200);
  }
}

TEST(Render, CanvasUsesFourSamplesAndAntiAliases) {
  GlCanvas canvas(64, 64, 1);
  EXPECT_EQ(canvas.samples(), 4);
  canvas.clear({1, 1, 1, 1});
  Triangles line;
  appendStroke(line, {{4, 4}, {60, 30}}, 2.0);
  canvas.fill(line, {0, 0, 0, 1});
  const Image image = canvas.read();
  int partial = 0;
  for (int y = 0; y < 64; ++y) {
    for (int x = 0; x < 64; ++x) partial += image.pixel(x, y)[0] > 10 && image.pixel(x, y)[0] < 245;
  }
  EXPECT_GT(partial, 40);  // a diagonal edge has partly covered pixels all along it
}

TEST(Render, TranslucentStrokeDoesNotDarkenAtJoints) {
  // Round joins overlap the segment quads; the stencil keeps every sample painted once, so a
  // 50 % black stroke is 50 % grey everywhere, joints included.
  GlCanvas canvas(64, 64, 1);
  canvas.clear({1, 1, 1, 1});
  Triangles stroke;
  appendStroke(stroke, {{8, 32}, {32, 32}, {32, 56}}, 8.0);  // a right-angle turn
  canvas.fill(stroke, {0, 0, 0, 0.5});
  const Image image = canvas.read();
  EXPECT_NEAR(image.pixel(32, 32)[0], 128, 1);  // joint: disc and both quads overlap here
  EXPECT_NEAR(image.pixel(34, 34)[0], 128, 1);  // inside the corner, both quads overlap
  EXPECT_NEAR(image.pixel(20, 32)[0], 128, 1);  // on a segment
}

TEST(Render, ConcurrentRendersMatchSerialOnes) {
  // Renders share one OSMesa context behind a mutex; each thread makes it current in turn.
  const Figure a{.width_px = 300, .height_px = 200, .axes = {samples::trajectoryAxes()}};
  const Figure b{.width_px = 300, .height_px = 200, .axes = {samples::deskewAxes()}};
  const Image serial_a = render(a), serial_b = render(b);
  Image threaded_a, threaded_b;
  std::thread ta([&] { threaded_a = render(a); });
  std::thread tb([&] { threaded_b = render(b); });
  ta.join();
  tb.join();
  EXPECT_EQ(threaded_a.rgba, serial_a.rgba);
  EXPECT_EQ(threaded_b.rgba, serial_b.rgba);
}

TEST(Render, AFigureDrawsTheSameInTheLargerBuffersOfEarlierOnes) {
  // The shared framebuffers only grow; a figure draws in their bottom-left corner. Drawn first
  // (buffers its own size when this test runs alone, as under ctest), then after a wider and a
  // taller figure grew them, the same figure must give the same bytes.
  const Figure small{.width_px = 300, .height_px = 200, .axes = {samples::trajectoryAxes()}};
  const Figure wide{.width_px = 520, .height_px = 150, .axes = {samples::deskewAxes()}};
  const Figure tall{.width_px = 200, .height_px = 430, .axes = {samples::scanAxes()}};
  const Image first = render(small);
  const Image wide_image = render(wide);
  const Image tall_image = render(tall);
  const Image again = render(small);
  EXPECT_EQ(again.width, 300);
  EXPECT_EQ(again.height, 200);
  EXPECT_EQ(again.rgba, first.rgba);
  EXPECT_EQ(render(wide).rgba, wide_image.rgba);  // in the buffers grown by the tall one
  EXPECT_EQ(tall_image.height, 430);
}

TEST(Render, FontScaleGrowsTheMargins) {
  Axes axes{.x_label = "x", .y_label = "y", .x_range = Range{0, 1}, .y_range = Range{0, 1}};
  Figure normal = plain(axes), large = plain(axes);
  large.font_scale = 1.5;
  const PanelLayout n = layoutFigure(normal).at(0), l = layoutFigure(large).at(0);
  EXPECT_GT(l.left_px, n.left_px + 10);  // wider tick labels and a taller rotated label
  EXPECT_LT(l.bottom_px, n.bottom_px - 10);
}

}  // namespace
}  // namespace slamprep::eval::plot

namespace slamprep::eval::plot {
namespace {

// An Outside legend narrows the plot area by its width and is drawn in the space freed, so it
// covers no data; an inset takes no grid cell and sits where it is put.
TEST(Render, OutsideLegendLeavesThePlotAreaToTheData) {
  Figure fig{.width_px = 600, .height_px = 400};
  Axes axes{.legend = LegendPosition::None};
  axes.series.push_back({.label = "a rather long method name", .x = {0, 1}, .y = {0, 1}});
  fig.axes = {axes};
  const double right_none = layoutFigure(fig)[0].right_px;
  fig.axes[0].legend = LegendPosition::Outside;
  const PanelLayout outside = layoutFigure(fig)[0];
  EXPECT_LT(outside.right_px, right_none - 150.0);
  const Image image = render(fig);
  bool ink_right_of_plot = false;  // the legend's text, beside the plot area
  for (int y = static_cast<int>(outside.top_px); y < static_cast<int>(outside.top_px) + 40; ++y)
    for (int x = static_cast<int>(outside.right_px) + 20; x < fig.width_px - 5; ++x)
      ink_right_of_plot = ink_right_of_plot || image.pixel(x, y)[0] < 128;
  EXPECT_TRUE(ink_right_of_plot);
  Axes inset{.inset = std::array<double, 4>{0.6, 0.1, 0.9, 0.4}};
  inset.series.push_back({.x = {0, 1}, .y = {0, 1}});
  fig.axes.push_back(inset);
  const auto layouts = layoutFigure(fig);  // a 1x1 grid holds the main panel and the inset
  ASSERT_EQ(layouts.size(), 2u);
  EXPECT_GT(layouts[1].left_px, 0.6 * fig.width_px);
  EXPECT_LT(layouts[1].bottom_px, 0.4 * fig.height_px);
}

}  // namespace
}  // namespace slamprep::eval::plot
