#include "sim/physics/world.hpp"

#include "core/error.hpp"

namespace slamprep::sim {

World loadWorld(const std::filesystem::path& file) {
  throw InputError(file.string(), "loadWorld: not implemented yet");
}

std::vector<std::vector<Eigen::Vector2d>> outline(const World&) {
  return {};
}

}  // namespace slamprep::sim
