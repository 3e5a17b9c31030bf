#include "slamprep/eval/plot/osmesa_library.hpp"

#include <dlfcn.h>

#include <stdexcept>

namespace slamprep::eval::plot {
namespace {

template <typename F>
void symbol(void* handle, const std::string& library, F& f, const char* name) {
  f = reinterpret_cast<F>(dlsym(handle, name));
  if (!f) throw std::runtime_error("plot: " + library + " lacks " + name);
}

template <typename F>
void procedure(const OsMesaLibrary& lib, F& f, const char* name) {
  f = reinterpret_cast<F>(lib.getProcAddress(name));
  if (!f) throw std::runtime_error("plot: " + lib.name + " lacks " + name);
}

void resolveExported(void* handle, OsMesaLibrary& lib) {
  const std::string& n = lib.name;
  symbol(handle, n, lib.createContextAttribs, "OSMesaCreateContextAttribs");
  symbol(handle, n, lib.makeCurrent, "OSMesaMakeCurrent");
  symbol(handle, n, lib.getProcAddress, "OSMesaGetProcAddress");
  symbol(handle, n, lib.getError, "glGetError");
  symbol(handle, n, lib.getIntegerv, "glGetIntegerv");
  symbol(handle, n, lib.isEnabled, "glIsEnabled");
  symbol(handle, n, lib.enable, "glEnable");
  symbol(handle, n, lib.disable, "glDisable");
  symbol(handle, n, lib.enableClientState, "glEnableClientState");
  symbol(handle, n, lib.viewport, "glViewport");
  symbol(handle, n, lib.matrixMode, "glMatrixMode");
  symbol(handle, n, lib.loadIdentity, "glLoadIdentity");
  symbol(handle, n, lib.ortho, "glOrtho");
  symbol(handle, n, lib.scissor, "glScissor");
  symbol(handle, n, lib.clearColor, "glClearColor");
  symbol(handle, n, lib.clearStencil, "glClearStencil");
  symbol(handle, n, lib.clear, "glClear");
  symbol(handle, n, lib.stencilFunc, "glStencilFunc");
  symbol(handle, n, lib.stencilOp, "glStencilOp");
  symbol(handle, n, lib.color4d, "glColor4d");
  symbol(handle, n, lib.vertexPointer, "glVertexPointer");
  symbol(handle, n, lib.drawArrays, "glDrawArrays");
  symbol(handle, n, lib.pixelStorei, "glPixelStorei");
  symbol(handle, n, lib.readPixels, "glReadPixels");
}

/// GL >= 3.0 is not in the GL 1.x symbol table every OpenGL library exports; OSMesa hands it out.
void resolveGl3(OsMesaLibrary& lib) {
  procedure(lib, lib.genFramebuffers, "glGenFramebuffers");
  procedure(lib, lib.deleteFramebuffers, "glDeleteFramebuffers");
  procedure(lib, lib.bindFramebuffer, "glBindFramebuffer");
  procedure(lib, lib.framebufferRenderbuffer, "glFramebufferRenderbuffer");
  procedure(lib, lib.checkFramebufferStatus, "glCheckFramebufferStatus");
  procedure(lib, lib.genRenderbuffers, "glGenRenderbuffers");
  procedure(lib, lib.deleteRenderbuffers, "glDeleteRenderbuffers");
  procedure(lib, lib.bindRenderbuffer, "glBindRenderbuffer");
  procedure(lib, lib.renderbufferStorageMultisample, "glRenderbufferStorageMultisample");
  procedure(lib, lib.blitFramebuffer, "glBlitFramebuffer");
  procedure(lib, lib.blendFuncSeparate, "glBlendFuncSeparate");
}

}  // namespace

OsMesaLibrary loadOsMesa(const std::vector<std::string>& file_names) {
  std::string tried, reason;
  for (const std::string& file_name : file_names) {
    // RTLD_LOCAL: its GL symbols stay out of the global scope, where a libGL could meet them.
    if (void* handle = dlopen(file_name.c_str(), RTLD_NOW | RTLD_LOCAL)) {
      OsMesaLibrary lib;
      lib.name = file_name;
      resolveExported(handle, lib);
      resolveGl3(lib);
      return lib;  // never dlclose'd: Mesa keeps per-thread state until exit
    }
    tried += (tried.empty() ? "" : ", ") + file_name;
    const char* error = dlerror();
    reason = error ? error : "not found";
  }
  throw std::runtime_error("plot: cannot load OSMesa (tried " + tried + "; " + reason +
                           "); plots need Mesa's off-screen renderer (Debian: libosmesa6)");
}

const OsMesaLibrary& osmesa() {
  static const OsMesaLibrary library = loadOsMesa();  // a throw leaves it for the next call
  return library;
}

}  // namespace slamprep::eval::plot
