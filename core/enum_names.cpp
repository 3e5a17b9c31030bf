#include "slamprep/core/enum_names.hpp"

namespace slamprep {

std::string unknownNameMessage(std::string_view what, std::string_view text,
                               const std::vector<std::string>& valid) {
  std::string message = "unknown " + std::string(what) + " '" + std::string(text) + "' (valid: ";
  for (std::size_t i = 0; i < valid.size(); ++i) message += (i ? ", " : "") + valid[i];
  return message + ")";
}

}  // namespace slamprep
