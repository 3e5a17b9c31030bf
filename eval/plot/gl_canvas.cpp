#include "slamprep/eval/plot/gl_canvas.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

#include "slamprep/eval/plot/osmesa_library.hpp"

namespace slamprep::eval::plot {
namespace {

constexpr int kMsaaSamples = 4;  ///< llvmpipe's GL_MAX_SAMPLES

/// llvmpipe is slow to touch fresh memory (a 4x MSAA 2400x1600 colour buffer takes ~0.6 s here),
/// so one context with its framebuffers is kept for the process and reused for every figure that
/// fits: a figure draws into the bottom-left corner, where GL's window coordinates start, so its
/// pixels do not depend on the buffer around it. A mutex serialises renders; the canvas is made
/// current on the rendering thread.
struct SharedGl {
  OSMesaContext context = nullptr;
  std::vector<unsigned char> dummy = std::vector<unsigned char>(16 * 16 * 4);  ///< OSMesa's own
  const OsMesaLibrary& gl = osmesa();  ///< loaded with the first canvas; a throw is retried
  GLuint msaa_fbo = 0, resolve_fbo = 0;
  GLuint msaa_color = 0, msaa_stencil = 0, resolve_color = 0;
  int width = 0, height = 0, scale = 0;     ///< the figure being drawn
  int buffer_width = 0, buffer_height = 0;  ///< the framebuffers' size in samples, >= the figure's
  int samples = 0;
  std::vector<unsigned char> pixels;  ///< glReadPixels target, reused
  int stencil_ref = 0;                ///< stencil value of the last no-overlap fill

  void makeCurrent() {
    if (!context) {
      const int attribs[] = {OSMESA_FORMAT,
                             OSMESA_RGBA,
                             OSMESA_DEPTH_BITS,
                             0,
                             OSMESA_STENCIL_BITS,
                             0,
                             OSMESA_ACCUM_BITS,
                             0,
                             OSMESA_PROFILE,
                             OSMESA_COMPAT_PROFILE,
                             OSMESA_CONTEXT_MAJOR_VERSION,
                             3,
                             OSMESA_CONTEXT_MINOR_VERSION,
                             0,
                             0};
      context = gl.createContextAttribs(attribs, nullptr);
      if (!context) {
        throw std::runtime_error(
            "plot: OSMesa context creation failed (is libGL linked beside libOSMesa?)");
      }
    }
    if (!gl.makeCurrent(context, dummy.data(), GL_UNSIGNED_BYTE, 16, 16)) {
      throw std::runtime_error("plot: OSMesaMakeCurrent failed");
    }
  }

  void deleteFramebuffers() {
    if (msaa_fbo == 0) return;
    const GLuint fbos[] = {msaa_fbo, resolve_fbo};
    const GLuint rbs[] = {msaa_color, msaa_stencil, resolve_color};
    gl.bindFramebuffer(GL_FRAMEBUFFER, 0);
    gl.deleteFramebuffers(2, fbos);
    gl.deleteRenderbuffers(3, rbs);
    msaa_fbo = resolve_fbo = msaa_color = msaa_stencil = resolve_color = 0;
    buffer_width = buffer_height = 0;
  }

  GLuint renderbuffer(int samples_wanted, GLenum format) {
    GLuint rb = 0;
    gl.genRenderbuffers(1, &rb);
    gl.bindRenderbuffer(GL_RENDERBUFFER, rb);
    gl.renderbufferStorageMultisample(GL_RENDERBUFFER, samples_wanted, format, buffer_width,
                                      buffer_height);
    return rb;
  }

  void checkComplete(const char* which) {
    const GLenum status = gl.checkFramebufferStatus(GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
      deleteFramebuffers();
      throw std::runtime_error(std::string("plot: OSMesa ") + which +
                               " framebuffer incomplete (status " + std::to_string(status) + ")");
    }
  }

  /// Grows the framebuffers to hold a w x h figure at supersample s; never shrinks them.
  void ensureFramebuffers(int w, int h, int s) {
    if (w * s <= buffer_width && h * s <= buffer_height) {
      width = w, height = h, scale = s;
      return;
    }
    const int grown_width = std::max(buffer_width, w * s);
    const int grown_height = std::max(buffer_height, h * s);
    deleteFramebuffers();
    GLint max_size = 0;
    gl.getIntegerv(GL_MAX_RENDERBUFFER_SIZE, &max_size);
    if (w * s > max_size || h * s > max_size) {
      throw std::runtime_error("plot: " + std::to_string(w * s) + "x" + std::to_string(h * s) +
                               " samples exceed GL_MAX_RENDERBUFFER_SIZE " +
                               std::to_string(max_size) + "; lower Figure::supersample");
    }
    width = w, height = h, scale = s;
    buffer_width = grown_width, buffer_height = grown_height;
    gl.genFramebuffers(1, &msaa_fbo);
    gl.bindFramebuffer(GL_FRAMEBUFFER, msaa_fbo);
    msaa_color = renderbuffer(kMsaaSamples, GL_RGBA8);
    gl.framebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, msaa_color);
    checkComplete("multisample");
    gl.getIntegerv(GL_SAMPLES, &samples);

    gl.genFramebuffers(1, &resolve_fbo);
    gl.bindFramebuffer(GL_FRAMEBUFFER, resolve_fbo);
    resolve_color = renderbuffer(0, GL_RGBA8);
    gl.framebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER,
                               resolve_color);
    checkComplete("resolve");
  }

  /// The stencil buffer is as large as the colour buffer and only translucent strokes need it, so
  /// it is attached on first use.
  void ensureStencil() {
    if (msaa_stencil != 0) return;
    gl.bindFramebuffer(GL_FRAMEBUFFER, msaa_fbo);
    msaa_stencil = renderbuffer(kMsaaSamples, GL_DEPTH24_STENCIL8);
    gl.framebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER,
                               msaa_stencil);
    checkComplete("multisample stencil");
    const GLboolean scissor = gl.isEnabled(GL_SCISSOR_TEST);
    gl.disable(GL_SCISSOR_TEST);
    gl.clear(GL_STENCIL_BUFFER_BIT);
    if (scissor) gl.enable(GL_SCISSOR_TEST);
    stencil_ref = 0;
  }

  void setupState() {
    gl.bindFramebuffer(GL_FRAMEBUFFER, msaa_fbo);
    gl.viewport(0, 0, width * scale, height * scale);
    gl.matrixMode(GL_PROJECTION);
    gl.loadIdentity();
    gl.ortho(0.0, width, height, 0.0, -1.0, 1.0);  // pixel units, origin top left, y down
    gl.matrixMode(GL_MODELVIEW);
    gl.loadIdentity();
    gl.disable(GL_DEPTH_TEST);
    gl.disable(GL_CULL_FACE);
    gl.disable(GL_SCISSOR_TEST);
    gl.disable(GL_STENCIL_TEST);
    gl.enable(GL_MULTISAMPLE);
    gl.enable(GL_BLEND);
    gl.blendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
    gl.enableClientState(GL_VERTEX_ARRAY);
    gl.clearStencil(0);
    if (msaa_stencil != 0) gl.clear(GL_STENCIL_BUFFER_BIT);
    stencil_ref = 0;
  }
};

std::mutex& sharedMutex() {
  static std::mutex mutex;
  return mutex;
}

SharedGl& shared() {
  static SharedGl gl;  // never destroyed before exit; the process owns it
  return gl;
}

}  // namespace

struct GlCanvas::Impl {
  std::unique_lock<std::mutex> lock{sharedMutex()};
  SharedGl& m = shared();
};

GlCanvas::GlCanvas(int width_px, int height_px, int supersample) : impl_(new Impl) {
  assert(width_px > 0 && height_px > 0 && supersample >= 1);
  SharedGl& m = impl_->m;
  m.makeCurrent();
  m.ensureFramebuffers(width_px, height_px, supersample);
  m.setupState();
  if (m.gl.getError() != GL_NO_ERROR) throw std::runtime_error("plot: OpenGL setup failed");
}

GlCanvas::~GlCanvas() = default;

int GlCanvas::samples() const {
  return impl_->m.samples;
}

void GlCanvas::clear(const Color& c) {
  const OsMesaLibrary& gl = impl_->m.gl;
  gl.disable(GL_SCISSOR_TEST);
  gl.clearColor(static_cast<GLfloat>(c.r), static_cast<GLfloat>(c.g), static_cast<GLfloat>(c.b),
                static_cast<GLfloat>(c.a));
  gl.clear(GL_COLOR_BUFFER_BIT);
}

void GlCanvas::setClip(const PixelRect& r) {
  const OsMesaLibrary& gl = impl_->m.gl;
  const int s = impl_->m.scale;
  const int left = static_cast<int>(std::floor(r.left));
  const int right = static_cast<int>(std::ceil(r.right));
  const int top = static_cast<int>(std::floor(r.top));
  const int bottom = static_cast<int>(std::ceil(r.bottom));
  gl.enable(GL_SCISSOR_TEST);
  // GL windows count rows from the bottom.
  gl.scissor(left * s, (impl_->m.height - bottom) * s, std::max(0, right - left) * s,
             std::max(0, bottom - top) * s);
}

void GlCanvas::clearClip() {
  impl_->m.gl.disable(GL_SCISSOR_TEST);
}

void GlCanvas::fill(const Triangles& triangles, const Color& c, bool no_overlap) {
  if (triangles.empty()) return;
  SharedGl& m = impl_->m;
  const OsMesaLibrary& gl = m.gl;
  std::vector<GLfloat> xy;
  xy.reserve(triangles.size() * 2);
  for (const Vec2& v : triangles) {
    xy.push_back(static_cast<GLfloat>(v.x));
    xy.push_back(static_cast<GLfloat>(v.y));
  }
  // Overlaps only show when the colour is translucent; opaque fills skip the stencil.
  no_overlap = no_overlap && c.a < 1.0;
  if (no_overlap) {
    m.ensureStencil();
    // Each fill stamps its own stencil value and skips samples that already carry it, so no
    // per-fill stencil clear (a full-buffer clear costs ~50 ms here); clear once per 255 fills.
    if (++m.stencil_ref > 255) {
      const GLboolean scissor = gl.isEnabled(GL_SCISSOR_TEST);
      gl.disable(GL_SCISSOR_TEST);
      gl.clear(GL_STENCIL_BUFFER_BIT);
      if (scissor) gl.enable(GL_SCISSOR_TEST);
      m.stencil_ref = 1;
    }
    gl.enable(GL_STENCIL_TEST);
    gl.stencilFunc(GL_NOTEQUAL, m.stencil_ref, 0xFF);
    gl.stencilOp(GL_KEEP, GL_KEEP, GL_REPLACE);
  }
  gl.color4d(c.r, c.g, c.b, c.a);
  gl.vertexPointer(2, GL_FLOAT, 0, xy.data());
  gl.drawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(triangles.size()));
  if (no_overlap) gl.disable(GL_STENCIL_TEST);
}

Image GlCanvas::read() {
  SharedGl& m = impl_->m;
  const OsMesaLibrary& gl = m.gl;
  const int sw = m.width * m.scale, sh = m.height * m.scale;
  gl.disable(GL_SCISSOR_TEST);
  gl.bindFramebuffer(GL_READ_FRAMEBUFFER, m.msaa_fbo);
  gl.bindFramebuffer(GL_DRAW_FRAMEBUFFER, m.resolve_fbo);
  gl.blitFramebuffer(0, 0, sw, sh, 0, 0, sw, sh, GL_COLOR_BUFFER_BIT, GL_NEAREST);
  gl.bindFramebuffer(GL_READ_FRAMEBUFFER, m.resolve_fbo);
  m.pixels.resize(static_cast<std::size_t>(sw) * sh * 4);
  const std::vector<unsigned char>& samples = m.pixels;
  gl.pixelStorei(GL_PACK_ALIGNMENT, 1);
  gl.readPixels(0, 0, sw, sh, GL_RGBA, GL_UNSIGNED_BYTE, m.pixels.data());
  gl.bindFramebuffer(GL_FRAMEBUFFER, m.msaa_fbo);
  if (gl.getError() != GL_NO_ERROR) throw std::runtime_error("plot: reading the pixels failed");

  Image image{m.width, m.height,
              std::vector<std::uint8_t>(static_cast<std::size_t>(m.width) * m.height * 4)};
  const int s = m.scale, area = s * s;
  for (int y = 0; y < m.height; ++y) {
    const int gl_row = (m.height - 1 - y) * s;  // GL row 0 is the bottom
    for (int x = 0; x < m.width; ++x) {
      int sum[4] = {0, 0, 0, 0};
      for (int dy = 0; dy < s; ++dy) {
        const unsigned char* p = &samples[(static_cast<std::size_t>(gl_row + dy) * sw + x * s) * 4];
        for (int dx = 0; dx < s; ++dx, p += 4) {
          for (int c = 0; c < 4; ++c) sum[c] += p[c];
        }
      }
      std::uint8_t* out = &image.rgba[(static_cast<std::size_t>(y) * m.width + x) * 4];
      for (int c = 0; c < 4; ++c) out[c] = static_cast<std::uint8_t>((sum[c] + area / 2) / area);
    }
  }
  return image;
}

}  // namespace slamprep::eval::plot
