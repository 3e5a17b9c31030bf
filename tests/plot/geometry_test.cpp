#include "slamprep/eval/plot/geometry.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace slamprep::eval::plot {
namespace {

double area(const Triangles& t) {
  double sum = 0.0;
  for (std::size_t i = 0; i + 2 < t.size(); i += 3) {
    sum += 0.5 * std::abs((t[i + 1].x - t[i].x) * (t[i + 2].y - t[i].y) -
                          (t[i + 2].x - t[i].x) * (t[i + 1].y - t[i].y));
  }
  return sum;
}

double length(const std::vector<Vec2>& line) {
  double sum = 0.0;
  for (std::size_t i = 1; i < line.size(); ++i) {
    sum += std::hypot(line[i].x - line[i - 1].x, line[i].y - line[i - 1].y);
  }
  return sum;
}

TEST(Geometry, StrokeOfOneSegmentIsLengthTimesWidth) {
  Triangles t;
  appendStroke(t, {{0, 0}, {30, 40}}, 3.0);
  EXPECT_NEAR(area(t), 50.0 * 3.0, 1e-9);
}

TEST(Geometry, DiscAreaWithinChordErrorBound) {
  // Chord error <= 0.05 px by construction, so the deficit is below 2 pi r * 0.05.
  for (const double r : {1.0, 4.0, 20.0}) {
    Triangles t;
    appendDisc(t, {5, 5}, r);
    const double exact = std::numbers::pi * r * r;
    EXPECT_LE(area(t), exact);
    EXPECT_GE(area(t), exact - 2.0 * std::numbers::pi * r * 0.05);
  }
}

TEST(Geometry, DashesFollowThePattern) {
  // 100 px with 10 on / 5 off: dashes start at 0, 15, ..., 90 -> 7 dashes of 10 px.
  const auto dashes = dashPolyline({{0, 0}, {50, 0}, {50, 50}}, 10.0, 5.0);
  ASSERT_EQ(dashes.size(), 7u);
  for (const auto& d : dashes) EXPECT_NEAR(length(d), 10.0, 1e-9);
  // The dash from 45 to 55 px crosses the corner: it keeps the corner vertex.
  ASSERT_EQ(dashes[3].size(), 3u);
  EXPECT_DOUBLE_EQ(dashes[3][1].x, 50.0);
  EXPECT_DOUBLE_EQ(dashes[3][1].y, 0.0);
}

TEST(Geometry, ClipSegment) {
  const PixelRect box{0, 0, 10, 10};
  Vec2 a{2, 2}, b{8, 3};
  ASSERT_TRUE(clipSegment(a, b, box));
  EXPECT_DOUBLE_EQ(a.x, 2.0);
  EXPECT_DOUBLE_EQ(b.x, 8.0);
  a = {-10, 5}, b = {20, 5};
  ASSERT_TRUE(clipSegment(a, b, box));
  EXPECT_DOUBLE_EQ(a.x, 0.0);
  EXPECT_DOUBLE_EQ(b.x, 10.0);
  a = {-10, -1}, b = {20, -1};
  EXPECT_FALSE(clipSegment(a, b, box));
  a = {-5, 5}, b = {5, 15};  // passes the corner region diagonally
  ASSERT_TRUE(clipSegment(a, b, box));
  EXPECT_NEAR(a.x, 0.0, 1e-12);
  EXPECT_NEAR(a.y, 10.0, 1e-12);
  EXPECT_NEAR(b.x, 0.0, 1e-12);
}

TEST(Geometry, ClipPolylineSplitsWhereItLeaves) {
  const PixelRect box{0, 0, 10, 10};
  const auto parts = clipPolyline({{1, 1}, {5, 1}, {20, 1}, {20, 5}, {5, 5}, {1, 5}}, box);
  ASSERT_EQ(parts.size(), 2u);
  EXPECT_EQ(parts[0].size(), 3u);  // (1,1) (5,1) (10,1)
  EXPECT_DOUBLE_EQ(parts[0].back().x, 10.0);
  EXPECT_EQ(parts[1].size(), 3u);  // (10,5) (5,5) (1,5)
  EXPECT_DOUBLE_EQ(parts[1].front().x, 10.0);
}

TEST(Geometry, MarkersHaveComparableArea) {
  // Shapes are sized so that none looks much heavier than the circle of the same size.
  Triangles circle;
  appendMarker(circle, Marker::Circle, {0, 0}, 10.0, 1.5);
  for (const Marker m : {Marker::Square, Marker::Triangle, Marker::Diamond, Marker::TriangleDown}) {
    Triangles t;
    appendMarker(t, m, {0, 0}, 10.0, 1.5);
    EXPECT_GT(area(t), 0.6 * area(circle));
    EXPECT_LT(area(t), 1.3 * area(circle));
  }
}

}  // namespace
}  // namespace slamprep::eval::plot
