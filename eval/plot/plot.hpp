#pragma once
// Off-screen figures: OSMesa draws the geometry (4x MSAA, optionally supersampled), FreeType draws
// the text, libpng writes the file. No display, no GPU. Same figure -> same bytes.
//
// Everything is a value type; build a Figure with designated initialisers and call renderPng():
//
//   Figure fig{.title = "De-skew error"};
//   fig.axes.push_back({.x_label = "yaw rate [rad/s]", .y_label = "error [m]", .log_y = true});
//   fig.axes[0].series.push_back({.label = "linear", .x = w, .y = err, .style =
//   Style::LineMarkers}); renderPng(fig, "deskew.png");
//
// Labels accept a tiny markup: "^{...}" superscript, "_{...}" subscript (e.g. "r_{L} [m]",
// "10^{-3}"). Anything else, including a lone '_' or '^', is literal text (UTF-8).

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace slamprep::eval::plot {

/// A colour, sRGB components in [0, 1]; a is opacity.
struct Color {
  double r = 0.0;
  double g = 0.0;
  double b = 0.0;
  double a = 1.0;

  bool operator==(const Color&) const = default;
};

/// Colour from 0xRRGGBB.
Color rgb(std::uint32_t hex, double alpha = 1.0);

/// Okabe-Ito colour-blind-safe palette, ordered for lines on white (blue, vermillion, green,
/// purple, orange, sky blue, black, yellow).
const std::vector<Color>& defaultPalette();
/// defaultPalette()[i % size].
Color paletteColor(std::size_t i);

/// How a series is drawn.
enum class Style {
  Line,         ///< a polyline, broken at non-finite values
  Markers,      ///< one marker per point
  LineMarkers,  ///< both
  Points,       ///< small dots (point clouds, scans); marker_size_px is the dot diameter
  Bars,         ///< bars from 0 (linear y) or the axis bottom (log y); dodged on categorical axes
  /// A box plot per distinct x: the points sharing an x are one sample (boxStats); box from the
  /// first to the third quartile, a line at the median, Tukey whiskers, the points beyond them
  /// as dots (marker_size_px, default 4 px); dodged like bars on categorical axes.
  Box,
};

/// Marker shape; Auto picks by series index so series differ in shape as well as colour.
enum class Marker { Auto, Circle, Square, Triangle, Diamond, TriangleDown, Plus, Cross };

/// Where the legend goes. Auto picks the corner that covers the fewest data; Outside puts it to
/// the right of the plot area, which is narrowed to make room, so it never covers data.
enum class LegendPosition { Auto, UpperRight, UpperLeft, LowerLeft, LowerRight, Outside, None };

/// One data series. x and y have equal length; non-finite points (and y <= 0 on a log y axis,
/// x <= 0 on a log x axis) are skipped and break a line.
struct Series {
  std::string label{};              ///< legend text; empty: not in the legend
  std::vector<double> x{};          ///< abscissae (category index on categorical axes)
  std::vector<double> y{};          ///< ordinates
  std::vector<double> y_err{};      ///< empty, or one error (e.g. 1 sigma) per point, above it
  std::vector<double> y_err_low{};  ///< empty: y_err below too; else the error below each point
  Style style = Style::Line;        ///< how the points are drawn
  std::optional<Color> color{};     ///< unset: next palette colour
  double line_width_px = 2.0;       ///< stroke width of lines and error bars
  std::optional<double> marker_size_px{};  ///< marker extent; unset: 8 px (Points: 3 px dots)
  Marker marker = Marker::Auto;            ///< marker shape for Markers / LineMarkers
  bool dashed = false;                     ///< dashed line
  std::optional<double> bar_width{};       ///< bar width in x units; unset: fits the category slot
};

/// Disjoint line segments in data units, e.g. a world outline; drawn below the series.
struct Segments {
  std::string label{};                        ///< legend text; empty: not in the legend
  std::vector<std::array<double, 4>> xyxy{};  ///< each segment as {x0, y0, x1, y1}
  Color color = {0.25, 0.25, 0.25, 1.0};      ///< stroke colour
  double line_width_px = 1.5;                 ///< stroke width
  bool dashed = false;                        ///< dashed stroke
};

/// What a Style::Box draws of a sample.
struct BoxStats {
  std::size_t n = 0;               ///< sample size (finite values)
  double q1 = 0.0;                 ///< first quartile
  double median = 0.0;             ///< second quartile
  double q3 = 0.0;                 ///< third quartile
  double whisker_low = 0.0;        ///< smallest value >= q1 - 1.5 IQR (Tukey)
  double whisker_high = 0.0;       ///< largest value <= q3 + 1.5 IQR
  std::vector<double> outliers{};  ///< the values beyond the whiskers, ascending
};

/// Quartiles by linear interpolation between order statistics (position (n - 1) p of the sorted
/// sample, Hyndman and Fan type 7, as numpy and R default to), Tukey whiskers and outliers of
/// the finite values of `sample`; all zero with n = 0 when there are none.
BoxStats boxStats(std::vector<double> sample);

/// A closed interval of data values, min < max.
struct Range {
  double min = 0.0;
  double max = 1.0;
};

/// One panel: a coordinate frame with its data.
struct Axes {
  std::string title{};             ///< panel title above the plot area
  std::string x_label{};           ///< x axis label
  std::string y_label{};           ///< y axis label, drawn rotated
  bool log_x = false;              ///< logarithmic x axis (decades)
  bool log_y = false;              ///< logarithmic y axis (decades)
  bool equal_aspect = false;       ///< one data unit is as long in x as in y (linear only)
  std::optional<Range> x_range{};  ///< unset: data extent plus a 4 % margin
  std::optional<Range> y_range{};  ///< unset: data extent plus a 4 % margin
  bool grid = true;                ///< light grid at the major ticks
  LegendPosition legend = LegendPosition::Auto;  ///< legend placement
  std::vector<std::string> categories{};  ///< non-empty: categorical x, labels at x = 0, 1, ...
  /// Categorical x: series side by side within a category slot; false: each at its own x.
  bool dodge = true;
  /// An inset: the panel's cell as fractions of the figure (left, top, right, bottom) instead of
  /// its place in the grid; drawn on white over the panels before it.
  std::optional<std::array<double, 4>> inset{};
  std::vector<Segments> segments{};  ///< outlines, drawn first
  std::vector<Series> series{};      ///< data, drawn in order
};

/// A whole image: a title and a grid of panels.
struct Figure {
  int width_px = 1200;       ///< image width
  int height_px = 800;       ///< image height
  std::string title{};       ///< figure title (above all panels); empty: none
  int rows = 1;              ///< panel grid rows
  int cols = 1;              ///< panel grid columns
  std::vector<Axes> axes{};  ///< panels in row-major order, at most rows * cols
  double font_scale = 1.0;   ///< multiplies every font size (14-19 px at 1.0) and text spacing
  int supersample = 2;       ///< render at this multiple and box-filter down (on top of 4x MSAA)
  std::filesystem::path font_path =
      "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";  ///< TrueType font for all text
};

/// 8-bit RGBA pixels, row 0 at the top.
struct Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgba{};  ///< width * height * 4 bytes

  /// Pixel (x, y), y counted from the top. Asserts that (x, y) is inside.
  std::array<std::uint8_t, 4> pixel(int x, int y) const;
};

/// Where a panel ended up: plot area in pixels (origin top left) and the final data ranges.
struct PanelLayout {
  double left_px = 0.0;    ///< plot area left edge
  double top_px = 0.0;     ///< plot area top edge
  double right_px = 0.0;   ///< plot area right edge
  double bottom_px = 0.0;  ///< plot area bottom edge
  Range x{};               ///< visible x range
  Range y{};               ///< visible y range
  bool log_x = false;      ///< x mapping is logarithmic
  bool log_y = false;      ///< y mapping is logarithmic

  /// Data x to pixel column (continuous; pixel c covers [c, c+1)).
  double toPixelX(double x_data) const;
  /// Data y to pixel row (continuous, counted from the top).
  double toPixelY(double y_data) const;
};

/// Renders the figure to pixels. Throws InputError on an invalid figure (mismatched lengths,
/// bad ranges, missing font) and std::runtime_error when OSMesa fails.
Image render(const Figure& figure);

/// The layout render() uses, one entry per panel (for tests and annotations).
std::vector<PanelLayout> layoutFigure(const Figure& figure);

/// render() and writePng().
void renderPng(const Figure& figure, const std::filesystem::path& path);

/// Writes an 8-bit RGB PNG (alpha dropped; a tEXt "Software: slamprep" chunk, no time stamps)
/// atomically: a temporary file beside `path`, then rename. Throws InputError on failure.
void writePng(const Image& image, const std::filesystem::path& path);

/// Reads any PNG as 8-bit RGBA. Throws InputError when the file is missing or not a PNG.
Image readPng(const std::filesystem::path& path);

}  // namespace slamprep::eval::plot
