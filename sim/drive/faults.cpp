#include "sim/drive/faults.hpp"

namespace slamprep::sim {

std::string_view faultName(Fault fault) {
  for (const auto& [f, name] : kFaultNames)
    if (f == fault) return name;
  return "?";
}

std::string toString(const FaultSet& faults) {
  std::string out;
  for (const auto& [f, name] : kFaultNames)
    if (faults.has(f)) out.append(out.empty() ? "" : ",").append(name);
  return out.empty() ? "none" : out;
}

std::optional<FaultSet> parseFaultSet(std::string_view text, std::string* error) {
  FaultSet set;
  if (text == "none" || text.empty()) return set;
  if (text == "all") {
    for (const auto& [f, name] : kFaultNames) set.add(f);
    return set;
  }
  while (!text.empty()) {
    const std::size_t comma = text.find(',');
    const std::string_view item = text.substr(0, comma);
    bool known = false;
    for (const auto& [f, name] : kFaultNames)
      if (name == item) {
        set.add(f);
        known = true;
      }
    if (!known) {
      if (error) {
        *error = "unknown fault '" + std::string(item) + "' (none, all";
        for (const auto& [f, name] : kFaultNames) error->append(", ").append(name);
        error->append(")");
      }
      return std::nullopt;
    }
    text = comma == std::string_view::npos ? std::string_view{} : text.substr(comma + 1);
  }
  return set;
}

}  // namespace slamprep::sim
