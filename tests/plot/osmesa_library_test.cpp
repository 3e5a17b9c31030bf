#include "slamprep/eval/plot/osmesa_library.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

namespace slamprep::eval::plot {
namespace {

std::string loadError(const std::vector<std::string>& file_names) {
  try {
    loadOsMesa(file_names);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

TEST(OsMesaLibrary, LoadsDebiansSonameWithEveryEntryPoint) {
  const OsMesaLibrary lib = loadOsMesa();
  EXPECT_EQ(lib.name, "libOSMesa.so.8");  // libosmesa6, which scripts/install-deps.sh installs
  EXPECT_NE(lib.createContextAttribs, nullptr);
  EXPECT_NE(lib.makeCurrent, nullptr);
  EXPECT_NE(lib.readPixels, nullptr);
  EXPECT_NE(lib.blitFramebuffer, nullptr);
  EXPECT_NE(lib.blendFuncSeparate, nullptr);
}

TEST(OsMesaLibrary, FallsBackToTheNextFileName) {
  const OsMesaLibrary lib = loadOsMesa({"libslamprep-no-such-osmesa.so", "libOSMesa.so.8"});
  EXPECT_EQ(lib.name, "libOSMesa.so.8");
  EXPECT_NE(lib.getIntegerv, nullptr);
}

TEST(OsMesaLibrary, NamesEveryFileTriedWhenNoneLoads) {
  const std::string error = loadError({"libslamprep-no-such-osmesa.so.8", "libslamprep-none.so"});
  EXPECT_NE(error.find("cannot load OSMesa"), std::string::npos) << error;
  EXPECT_NE(error.find("tried libslamprep-no-such-osmesa.so.8, libslamprep-none.so;"),
            std::string::npos)
      << error;
  EXPECT_NE(error.find("libosmesa6"), std::string::npos) << error;  // what to install
}

TEST(OsMesaLibrary, NamesTheEntryPointALibraryLacks) {
  // libm loads but is no OpenGL library.
  EXPECT_EQ(loadError({"libm.so.6"}), "plot: libm.so.6 lacks OSMesaCreateContextAttribs");
}

}  // namespace
}  // namespace slamprep::eval::plot
