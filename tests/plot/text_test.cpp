#include "slamprep/eval/plot/text.hpp"

#include <gtest/gtest.h>

#include "slamprep/core/error.hpp"

namespace slamprep::eval::plot {
namespace {

const std::filesystem::path kFont = Figure{}.font_path;

Image whiteImage(int w, int h) {
  return {w, h, std::vector<std::uint8_t>(static_cast<std::size_t>(w) * h * 4, 255)};
}

/// Bounding box of pixels darker than 200 (any channel): {left, top, right, bottom}, inclusive.
std::array<int, 4> inkBox(const Image& image) {
  std::array<int, 4> box{image.width, image.height, -1, -1};
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      if (image.pixel(x, y)[0] < 200) {
        box = {std::min(box[0], x), std::min(box[1], y), std::max(box[2], x), std::max(box[3], y)};
      }
    }
  }
  return box;
}

TEST(Utf8, DecodesAndReplacesInvalidBytes) {
  EXPECT_EQ(decodeUtf8("a\xCF\x89\xC2\xB0"), (std::u32string{U'a', 0x3C9, 0xB0}));  // aω°
  EXPECT_EQ(decodeUtf8("\xE2\x88\x92"), std::u32string(1, 0x2212));
  EXPECT_EQ(decodeUtf8("x\xFFy"), (std::u32string{U'x', 0xFFFD, U'y'}));
  EXPECT_EQ(decodeUtf8("\xCF"), std::u32string(1, 0xFFFD));  // truncated sequence
}

TEST(Text, MissingFontIsAnInputError) {
  EXPECT_THROW(TextRenderer("/nonexistent/font.ttf"), InputError);
}

TEST(Text, MeasureGrowsWithTextAndSize) {
  TextRenderer text(kFont);
  const TextExtent a = text.measure("10", 14.0), b = text.measure("1000", 14.0);
  EXPECT_NEAR(b.width_px, 2.0 * a.width_px, 1.0);  // digits are tabular in DejaVu Sans
  EXPECT_NEAR(text.measure("10", 28.0).width_px, 2.0 * a.width_px, 1.0);
  // DejaVu Sans: ascender 0.928 em, descender 0.236 em.
  EXPECT_NEAR(a.ascent_px, 0.928 * 14.0, 1.0);
  EXPECT_NEAR(a.descent_px, 0.236 * 14.0, 1.0);
  const TextExtent power = text.measure("10^{3}", 14.0);
  EXPECT_GT(power.ascent_px, a.ascent_px + 2.0);  // the superscript rises above the line
  EXPECT_GT(power.width_px, a.width_px);
  EXPECT_LT(power.width_px, b.width_px);  // a script digit is narrower than a normal one
}

TEST(Text, HorizontalTextLandsInsideItsBox) {
  TextRenderer text(kFont);
  Image image = whiteImage(200, 60);
  const TextExtent e = text.measure("Hello 123", 16.0);
  text.draw(image, "Hello 123", 16.0, 20.0, 10.0, HAlign::Left, VAlign::Top, {0, 0, 0, 1});
  const auto box = inkBox(image);
  ASSERT_GE(box[2], 0) << "no ink at all";
  // Ink lies within the advance box [20, 20 + width] x [10, 10 + height], give or take the
  // side bearings (1 px) and the gap between the font ascender and the cap height.
  EXPECT_GE(box[0], 20);
  EXPECT_LE(box[0], 22);
  EXPECT_NEAR(box[2], 20 + e.width_px, 2.0);
  EXPECT_GE(box[1], 10);
  EXPECT_LE(box[3], 10 + e.height());
  int dark = 0;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) dark += image.pixel(x, y)[0] < 100;
  }
  EXPECT_GT(dark, 60);  // nine glyphs with 1.5 px stems
}

TEST(Text, AntiAliasedEdges) {
  TextRenderer text(kFont);
  Image image = whiteImage(100, 40);
  text.draw(image, "O", 24.0, 50.0, 20.0, HAlign::Center, VAlign::Middle, {0, 0, 0, 1});
  int grey = 0;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      const int v = image.pixel(x, y)[0];
      grey += v > 40 && v < 215;
    }
  }
  EXPECT_GT(grey, 10);  // the round outline produces intermediate coverage
}

TEST(Text, VerticalTextReadsUpwards) {
  TextRenderer text(kFont);
  Image image = whiteImage(60, 240);
  const TextExtent e = text.measure("vertical label", 16.0);
  text.draw(image, "vertical label", 16.0, 10.0, 120.0, HAlign::Center, VAlign::Top, {0, 0, 0, 1},
            true);
  const auto box = inkBox(image);
  ASSERT_GE(box[2], 0);
  const int ink_w = box[2] - box[0] + 1, ink_h = box[3] - box[1] + 1;
  EXPECT_GT(ink_h, 3 * ink_w);
  EXPECT_NEAR(ink_h, e.width_px, 3.0);
  EXPECT_NEAR((box[1] + box[3]) / 2.0, 120.0, 2.0);  // centred on the anchor along the text
  EXPECT_GE(box[0], 10);                             // the letter tops point left, to x = 10
  // Reading upwards, the text starts at the bottom: "v" (x-height only) is at the bottom,
  // "l" (ascender) at the top; an ascender reaches further left than an x-height letter.
  auto leftmost_ink_in_rows = [&](int y0, int y1) {
    int left = image.width;
    for (int y = y0; y <= y1; ++y) {
      for (int x = 0; x < image.width; ++x) {
        if (image.pixel(x, y)[0] < 200) left = std::min(left, x);
      }
    }
    return left;
  };
  EXPECT_LT(leftmost_ink_in_rows(box[1], box[1] + 3), leftmost_ink_in_rows(box[3] - 3, box[3]));
}

}  // namespace
}  // namespace slamprep::eval::plot
