#include "eval/bench/figures.hpp"

namespace slamprep::eval {

std::vector<std::string> renderSuitePlots(const Suite&, const nlohmann::json&,
                                          const std::filesystem::path&) {
  return {};  // filled in once trials record their artifacts
}

}  // namespace slamprep::eval
