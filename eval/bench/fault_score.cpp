#include "slamprep/eval/bench/fault_score.hpp"

#include <algorithm>
#include <cctype>

namespace slamprep::eval {
namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

}  // namespace

std::map<std::string, std::size_t> faultEventCounts(const Dataset& dataset) {
  std::map<std::string, std::size_t> out;
  const nlohmann::json& faults = dataset.info.faults;
  if (!faults.is_object() || !faults.contains("enabled")) return out;
  for (const auto& name : faults["enabled"]) {
    const nlohmann::json& record = faults[name.get<std::string>()];
    std::size_t count = 1;
    if (record.contains("count"))
      count = record["count"].get<std::size_t>();
    else if (record.contains("events"))
      count = record["events"].size();
    out[name.get<std::string>()] = count;
  }
  return out;
}

bool namesInjectedFault(const std::string& reason, const Dataset& dataset) {
  const nlohmann::json& faults = dataset.info.faults;
  if (!faults.is_object() || !faults.contains("enabled")) return false;
  const std::string text = lower(reason);
  for (const auto& entry : faults["enabled"]) {
    const std::string name = entry.get<std::string>();
    std::string words = name;
    std::replace(words.begin(), words.end(), '_', ' ');
    if (words.size() > 1 && words.back() == 's') words.pop_back();
    if (text.find(name) != std::string::npos || text.find(words) != std::string::npos) return true;
  }
  return false;
}

}  // namespace slamprep::eval
