#pragma once
// Text with FreeType: anti-aliased glyphs blended straight into an Image, horizontal or rotated by
// 90 degrees (reading upwards). Markup: "^{...}" superscript, "_{...}" subscript, UTF-8.

#include <filesystem>
#include <map>
#include <memory>
#include <string_view>
#include <vector>

#include "slamprep/eval/plot/plot.hpp"

namespace slamprep::eval::plot {

enum class HAlign { Left, Center, Right };
enum class VAlign { Top, Middle, Baseline, Bottom };

/// Extent of a line of text in pixels: advance width and the font's ascent/descent (not ink).
struct TextExtent {
  double width_px = 0.0;
  double ascent_px = 0.0;   ///< above the baseline
  double descent_px = 0.0;  ///< below the baseline (positive)

  double height() const { return ascent_px + descent_px; }
};

/// One FreeType face with a glyph cache. Not thread-safe; one per render.
class TextRenderer {
 public:
  /// Throws InputError(font_path, ...) when the font cannot be loaded.
  explicit TextRenderer(const std::filesystem::path& font_path);
  ~TextRenderer();
  TextRenderer(const TextRenderer&) = delete;
  TextRenderer& operator=(const TextRenderer&) = delete;

  TextExtent measure(std::string_view markup, double size_px);

  /// Draws `markup` so that the point given by (h, v) alignment of its box lies at (x_px, y_px).
  /// Vertical text is rotated 90 degrees counter-clockwise; alignments refer to the text's own
  /// reading direction (Left = where reading starts, Top = the side the letters point to).
  void draw(Image& image, std::string_view markup, double size_px, double x_px, double y_px,
            HAlign h, VAlign v, const Color& color, bool vertical = false);

 private:
  struct Glyph {
    int left = 0;  ///< bitmap offset from the pen position
    int top = 0;   ///< bitmap top above the baseline
    int width = 0;
    int rows = 0;
    long advance_26_6 = 0;  ///< pen advance in 1/64 px
    std::vector<unsigned char> coverage;
  };
  struct Run;
  struct Layout;

  const Glyph& glyph(char32_t code, long size_26_6);
  Layout layout(std::string_view markup, double size_px);

  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::map<std::pair<char32_t, long>, Glyph> cache_;
};

/// Decodes UTF-8; invalid bytes become U+FFFD.
std::u32string decodeUtf8(std::string_view text);

}  // namespace slamprep::eval::plot
