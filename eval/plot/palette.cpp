#include "slamprep/eval/plot/plot.hpp"

namespace slamprep::eval::plot {

Color rgb(std::uint32_t hex, double alpha) {
  return {((hex >> 16) & 0xFF) / 255.0, ((hex >> 8) & 0xFF) / 255.0, (hex & 0xFF) / 255.0, alpha};
}

const std::vector<Color>& defaultPalette() {
  // Okabe & Ito (2008), "Color Universal Design"; yellow last, it is faint on white.
  static const std::vector<Color> palette{rgb(0x0072B2), rgb(0xD55E00), rgb(0x009E73),
                                          rgb(0xCC79A7), rgb(0xE69F00), rgb(0x56B4E9),
                                          rgb(0x000000), rgb(0xF0E442)};
  return palette;
}

Color paletteColor(std::size_t i) {
  return defaultPalette()[i % defaultPalette().size()];
}

}  // namespace slamprep::eval::plot
