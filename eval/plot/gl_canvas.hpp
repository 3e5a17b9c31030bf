#pragma once
// An off-screen OSMesa (llvmpipe) canvas: a 4x multisampled framebuffer object at `supersample`
// times the image size; read() resolves the samples, box-filters down and flips to top-first rows.

#include <memory>

#include "slamprep/eval/plot/geometry.hpp"
#include "slamprep/eval/plot/plot.hpp"

namespace slamprep::eval::plot {

class GlCanvas {
 public:
  /// Throws std::runtime_error naming the failing step (loading libOSMesa, context, framebuffer)
  /// when OSMesa fails.
  GlCanvas(int width_px, int height_px, int supersample);
  ~GlCanvas();
  GlCanvas(const GlCanvas&) = delete;
  GlCanvas& operator=(const GlCanvas&) = delete;

  /// Fills the whole canvas (ignores the clip).
  void clear(const Color& color);
  /// Restricts drawing to a pixel rectangle (rounded outwards to whole pixels).
  void setClip(const PixelRect& rect);
  void clearClip();
  /// Draws a triangle list in `color` (alpha-blended). With `no_overlap` and a translucent colour,
  /// every sample is painted at most once by this call (stencil), so a translucent stroke stays
  /// even where its pieces overlap.
  void fill(const Triangles& triangles, const Color& color, bool no_overlap = true);
  /// The pixels so far.
  Image read();

  /// MSAA samples actually in use (GL_SAMPLES of the framebuffer).
  int samples() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace slamprep::eval::plot
