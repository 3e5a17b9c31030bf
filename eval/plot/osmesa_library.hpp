#pragma once
// libOSMesa, loaded at the first render (dlopen), not linked: linking it made every start of
// slamprep relocate libOSMesa and the libLLVM behind it, ~95 ms of CPU, although only plots draw
// (docs/design.md, "Bullet and OSMesa"). Every OSMesa and OpenGL call of the canvas goes through
// these pointers; the headers give their types only.

#include <GL/osmesa.h>
// clang-format off
#include <GL/gl.h>
#include <GL/glext.h>
// clang-format on

#include <string>
#include <vector>

namespace slamprep::eval::plot {

/// The entry points the canvas calls: OSMesa's and OpenGL 1.x's from the library's symbol table,
/// OpenGL >= 3.0's through OSMesaGetProcAddress.
struct OsMesaLibrary {
  std::string name;  ///< the file name dlopen loaded
  decltype(&::OSMesaCreateContextAttribs) createContextAttribs = nullptr;
  decltype(&::OSMesaMakeCurrent) makeCurrent = nullptr;
  decltype(&::OSMesaGetProcAddress) getProcAddress = nullptr;

  decltype(&::glGetError) getError = nullptr;
  decltype(&::glGetIntegerv) getIntegerv = nullptr;
  decltype(&::glIsEnabled) isEnabled = nullptr;
  decltype(&::glEnable) enable = nullptr;
  decltype(&::glDisable) disable = nullptr;
  decltype(&::glEnableClientState) enableClientState = nullptr;
  decltype(&::glViewport) viewport = nullptr;
  decltype(&::glMatrixMode) matrixMode = nullptr;
  decltype(&::glLoadIdentity) loadIdentity = nullptr;
  decltype(&::glOrtho) ortho = nullptr;
  decltype(&::glScissor) scissor = nullptr;
  decltype(&::glClearColor) clearColor = nullptr;
  decltype(&::glClearStencil) clearStencil = nullptr;
  decltype(&::glClear) clear = nullptr;
  decltype(&::glStencilFunc) stencilFunc = nullptr;
  decltype(&::glStencilOp) stencilOp = nullptr;
  decltype(&::glColor4d) color4d = nullptr;
  decltype(&::glVertexPointer) vertexPointer = nullptr;
  decltype(&::glDrawArrays) drawArrays = nullptr;
  decltype(&::glPixelStorei) pixelStorei = nullptr;
  decltype(&::glReadPixels) readPixels = nullptr;

  PFNGLGENFRAMEBUFFERSPROC genFramebuffers = nullptr;
  PFNGLDELETEFRAMEBUFFERSPROC deleteFramebuffers = nullptr;
  PFNGLBINDFRAMEBUFFERPROC bindFramebuffer = nullptr;
  PFNGLFRAMEBUFFERRENDERBUFFERPROC framebufferRenderbuffer = nullptr;
  PFNGLCHECKFRAMEBUFFERSTATUSPROC checkFramebufferStatus = nullptr;
  PFNGLGENRENDERBUFFERSPROC genRenderbuffers = nullptr;
  PFNGLDELETERENDERBUFFERSPROC deleteRenderbuffers = nullptr;
  PFNGLBINDRENDERBUFFERPROC bindRenderbuffer = nullptr;
  PFNGLRENDERBUFFERSTORAGEMULTISAMPLEPROC renderbufferStorageMultisample = nullptr;
  PFNGLBLITFRAMEBUFFERPROC blitFramebuffer = nullptr;
  PFNGLBLENDFUNCSEPARATEPROC blendFuncSeparate = nullptr;
};

/// Debian's libosmesa6 soname first, then the development link.
inline const std::vector<std::string> kOsMesaFileNames = {"libOSMesa.so.8", "libOSMesa.so"};

/// Opens the first of `file_names` that dlopen finds and resolves every entry point. Throws
/// std::runtime_error naming the files tried and dlopen's reason, or the missing entry point.
/// The library stays loaded for the process.
OsMesaLibrary loadOsMesa(const std::vector<std::string>& file_names = kOsMesaFileNames);

/// The process's OSMesa, loaded at the first call; throws as loadOsMesa (and again at the next
/// call) when it cannot be loaded.
const OsMesaLibrary& osmesa();

}  // namespace slamprep::eval::plot
