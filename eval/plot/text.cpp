#include "slamprep/eval/plot/text.hpp"

#include <ft2build.h>
#include FT_FREETYPE_H

#include <algorithm>
#include <cassert>
#include <cmath>

#include "slamprep/core/error.hpp"

namespace slamprep::eval::plot {

namespace {

constexpr double kScriptScale = 0.7;       ///< super/subscript size relative to the text
constexpr double kSuperscriptRise = 0.42;  ///< superscript baseline shift, in text sizes
constexpr double kSubscriptDrop = 0.16;    ///< subscript baseline shift, in text sizes
/// Coverage is raised to 1/gamma before blending: linear blending in sRGB makes dark text on white
/// look thinner than the glyph outline; 1.2 restores the stem weight without blurring.
constexpr double kCoverageGamma = 1.2;

/// A piece of text at one script level (0 normal, +1 superscript, -1 subscript).
struct Piece {
  std::u32string text;
  int level = 0;
};

std::vector<Piece> parseMarkup(std::string_view markup) {
  const std::u32string text = decodeUtf8(markup);
  std::vector<Piece> pieces(1);
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char32_t c = text[i];
    if ((c == U'^' || c == U'_') && i + 1 < text.size() && text[i + 1] == U'{') {
      std::size_t close = text.find(U'}', i + 2);
      if (close == std::u32string::npos) close = text.size();
      pieces.push_back({text.substr(i + 2, close - i - 2), c == U'^' ? 1 : -1});
      pieces.push_back({});
      i = close;
    } else {
      pieces.back().text.push_back(c);
    }
  }
  return pieces;
}

}  // namespace

std::u32string decodeUtf8(std::string_view text) {
  std::u32string out;
  for (std::size_t i = 0; i < text.size();) {
    const auto byte = static_cast<unsigned char>(text[i]);
    int extra = 0;
    char32_t code = 0;
    if (byte < 0x80) {
      code = byte;
    } else if ((byte & 0xE0) == 0xC0) {
      extra = 1, code = byte & 0x1F;
    } else if ((byte & 0xF0) == 0xE0) {
      extra = 2, code = byte & 0x0F;
    } else if ((byte & 0xF8) == 0xF0) {
      extra = 3, code = byte & 0x07;
    } else {
      out.push_back(0xFFFD), ++i;
      continue;
    }
    bool ok = i + extra < text.size();
    for (int k = 1; ok && k <= extra; ++k) {
      const auto next = static_cast<unsigned char>(text[i + k]);
      ok = (next & 0xC0) == 0x80;
      code = (code << 6) | (next & 0x3F);
    }
    if (!ok) {
      out.push_back(0xFFFD), ++i;
      continue;
    }
    out.push_back(code);
    i += extra + 1;
  }
  return out;
}

struct TextRenderer::Impl {
  FT_Library library = nullptr;
  FT_Face face = nullptr;
  long size_26_6 = 0;  ///< size currently set on the face

  ~Impl() {
    if (face) FT_Done_Face(face);
    if (library) FT_Done_FreeType(library);
  }

  void setSize(long size) {
    if (size == size_26_6) return;
    FT_Set_Char_Size(face, 0, size, 72, 72);  // 72 dpi: 1 pt = 1 px
    size_26_6 = size;
  }
};

/// A glyph placed on the line: integer pen position and baseline shift (up positive).
struct TextRenderer::Run {
  const Glyph* glyph = nullptr;
  int pen_x = 0;
  int rise = 0;
};

struct TextRenderer::Layout {
  std::vector<Run> runs;
  TextExtent extent;
  double base_ascent_px = 0.0;   ///< ascent of the main size alone
  double base_descent_px = 0.0;  ///< descent of the main size alone
};

TextRenderer::TextRenderer(const std::filesystem::path& font_path) : impl_(new Impl) {
  if (FT_Init_FreeType(&impl_->library) != 0) {
    throw InputError(font_path.string(), "FreeType could not be initialised");
  }
  if (FT_New_Face(impl_->library, font_path.c_str(), 0, &impl_->face) != 0) {
    throw InputError(font_path.string(), "cannot load font (missing or not a TrueType file)");
  }
}

TextRenderer::~TextRenderer() = default;

const TextRenderer::Glyph& TextRenderer::glyph(char32_t code, long size_26_6) {
  const auto key = std::make_pair(code, size_26_6);
  if (auto it = cache_.find(key); it != cache_.end()) return it->second;
  impl_->setSize(size_26_6);
  Glyph g;
  FT_Face face = impl_->face;
  if (FT_Load_Char(face, code, FT_LOAD_RENDER | FT_LOAD_TARGET_LIGHT) == 0 &&
      face->glyph->bitmap.pixel_mode == FT_PIXEL_MODE_GRAY) {
    const FT_Bitmap& bitmap = face->glyph->bitmap;
    g.left = face->glyph->bitmap_left;
    g.top = face->glyph->bitmap_top;
    g.width = static_cast<int>(bitmap.width);
    g.rows = static_cast<int>(bitmap.rows);
    g.advance_26_6 = face->glyph->advance.x;
    g.coverage.resize(static_cast<std::size_t>(g.width) * g.rows);
    for (int r = 0; r < g.rows; ++r) {
      const unsigned char* row = bitmap.buffer + static_cast<std::ptrdiff_t>(r) * bitmap.pitch;
      std::copy(row, row + g.width, g.coverage.begin() + static_cast<std::ptrdiff_t>(r) * g.width);
    }
  }
  return cache_.emplace(key, std::move(g)).first->second;
}

TextRenderer::Layout TextRenderer::layout(std::string_view markup, double size_px) {
  Layout out;
  FT_Face face = impl_->face;
  long pen_26_6 = 0;
  for (const Piece& piece : parseMarkup(markup)) {
    const double size = piece.level == 0 ? size_px : size_px * kScriptScale;
    const double rise = piece.level > 0   ? kSuperscriptRise * size_px
                        : piece.level < 0 ? -kSubscriptDrop * size_px
                                          : 0.0;
    const long size_26_6 = std::max(64L, std::lround(size * 64.0));
    impl_->setSize(size_26_6);
    if (piece.level == 0) {
      out.base_ascent_px = face->size->metrics.ascender / 64.0;
      out.base_descent_px = -face->size->metrics.descender / 64.0;
    }
    const double ascent = face->size->metrics.ascender / 64.0 + rise;
    const double descent = -face->size->metrics.descender / 64.0 - rise;
    if (!piece.text.empty() || piece.level != 0) {
      out.extent.ascent_px = std::max(out.extent.ascent_px, ascent);
      out.extent.descent_px = std::max(out.extent.descent_px, descent);
    }
    FT_UInt previous = 0;
    for (const char32_t code : piece.text) {
      impl_->setSize(size_26_6);
      const FT_UInt index = FT_Get_Char_Index(face, code);
      if (previous != 0 && index != 0 && FT_HAS_KERNING(face)) {
        FT_Vector kern{};
        FT_Get_Kerning(face, previous, index, FT_KERNING_DEFAULT, &kern);
        pen_26_6 += kern.x;
      }
      previous = index;
      const Glyph& g = glyph(code, size_26_6);
      out.runs.push_back(
          {&g, static_cast<int>((pen_26_6 + 32) >> 6), static_cast<int>(std::lround(rise))});
      pen_26_6 += g.advance_26_6;
    }
  }
  out.extent.width_px = pen_26_6 / 64.0;
  return out;
}

TextExtent TextRenderer::measure(std::string_view markup, double size_px) {
  return layout(markup, size_px).extent;
}

void TextRenderer::draw(Image& image, std::string_view markup, double size_px, double x_px,
                        double y_px, HAlign h, VAlign v, const Color& color, bool vertical) {
  const Layout line = layout(markup, size_px);
  const TextExtent& e = line.extent;
  // Anchor in text coordinates: u along the reading direction, w "down" across it (baseline 0).
  const double anchor_u = h == HAlign::Left     ? 0.0
                          : h == HAlign::Center ? e.width_px / 2
                                                : e.width_px;
  // Middle centres the main line (scripts ignored), so "10^{-2}" centres its "10" on a tick.
  const double anchor_w = v == VAlign::Top        ? -e.ascent_px
                          : v == VAlign::Middle   ? (line.base_descent_px - line.base_ascent_px) / 2
                          : v == VAlign::Baseline ? 0.0
                                                  : e.descent_px;
  // Integer origin keeps hinted glyphs crisp.
  const long origin_x = vertical ? std::lround(x_px - anchor_w) : std::lround(x_px - anchor_u);
  const long origin_y = vertical ? std::lround(y_px + anchor_u) : std::lround(y_px - anchor_w);

  const double alpha = std::clamp(color.a, 0.0, 1.0);
  const double src[3] = {color.r * 255.0, color.g * 255.0, color.b * 255.0};
  auto blend = [&](long sx, long sy, unsigned char coverage) {
    if (coverage == 0 || sx < 0 || sy < 0 || sx >= image.width || sy >= image.height) return;
    const double a = alpha * std::pow(coverage / 255.0, 1.0 / kCoverageGamma);
    std::uint8_t* p = &image.rgba[(static_cast<std::size_t>(sy) * image.width + sx) * 4];
    for (int c = 0; c < 3; ++c) {
      p[c] = static_cast<std::uint8_t>(std::lround(p[c] + (src[c] - p[c]) * a));
    }
  };
  // Composite the glyphs into one coverage mask first (max), so overlaps do not darken.
  long u0 = 0, u1 = 0, w0 = 0, w1 = 0;
  bool any = false;
  for (const Run& run : line.runs) {
    const Glyph& g = *run.glyph;
    if (g.width == 0 || g.rows == 0) continue;
    const long gu0 = run.pen_x + g.left, gw0 = -g.top - run.rise;
    u0 = any ? std::min(u0, gu0) : gu0;
    w0 = any ? std::min(w0, gw0) : gw0;
    u1 = any ? std::max(u1, gu0 + g.width) : gu0 + g.width;
    w1 = any ? std::max(w1, gw0 + g.rows) : gw0 + g.rows;
    any = true;
  }
  if (!any) return;
  const long mask_w = u1 - u0;
  std::vector<unsigned char> mask(static_cast<std::size_t>(mask_w * (w1 - w0)), 0);
  for (const Run& run : line.runs) {
    const Glyph& g = *run.glyph;
    for (int r = 0; r < g.rows; ++r) {
      for (int c = 0; c < g.width; ++c) {
        const long u = run.pen_x + g.left + c - u0;
        const long w = r - g.top - run.rise - w0;
        unsigned char& m = mask[static_cast<std::size_t>(w * mask_w + u)];
        m = std::max(m, g.coverage[static_cast<std::size_t>(r) * g.width + c]);
      }
    }
  }
  for (long w = w0; w < w1; ++w) {
    for (long u = u0; u < u1; ++u) {
      const unsigned char cov = mask[static_cast<std::size_t>((w - w0) * mask_w + (u - u0))];
      if (vertical) {
        blend(origin_x + w, origin_y - u - 1, cov);  // reading upwards, letter tops to the left
      } else {
        blend(origin_x + u, origin_y + w, cov);
      }
    }
  }
}

}  // namespace slamprep::eval::plot
