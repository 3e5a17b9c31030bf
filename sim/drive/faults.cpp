#include "slamprep/sim/drive/faults.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "slamprep/core/number_list.hpp"

namespace slamprep::sim {

std::string_view faultName(Fault fault) {
  return nameOf(kFaultNames, fault);
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
    const auto fault = findName(kFaultNames, item);
    if (!fault) {
      if (error) {
        std::vector<std::string> valid = {"none", "all"};
        for (const std::string& name : namesOf(kFaultNames)) valid.push_back(name);
        *error = unknownNameMessage("fault", item, valid);
      }
      return std::nullopt;
    }
    set.add(*fault);
    text = comma == std::string_view::npos ? std::string_view{} : text.substr(comma + 1);
  }
  return set;
}

std::optional<std::vector<double>> parseFactors(std::string_view text, std::string* error) {
  constexpr NumberListRule kFactors{0.0, std::numeric_limits<double>::max(), 3600,  // 0.1 deg bins
                                    "a number >= 0"};
  return parseNumberList(text, kFactors, error);
}

double periodJitter(SplitMix64& rng, double sigma_s, double rate_hz) {
  const double limit_s = 0.45 / rate_hz;
  return std::clamp(sigma_s * rng.gaussian(), -limit_s, limit_s);
}

ScanReadJitter::ScanReadJitter(const FaultsConfig& f, std::uint64_t seed, double lidar_hz)
    : sigma_s_(f.enable.has(Fault::read_jitter) ? f.read_jitter_scans_sigma_s : 0.0),
      lidar_hz_(lidar_hz),
      rng_(streamSeed(seed, RngStream::fault_read_jitter_scans)) {}

double ScanReadJitter::next() {
  if (sigma_s_ <= 0.0) return 0.0;
  const double e = periodJitter(rng_, sigma_s_, lidar_hz_);
  const bool first = std::exchange(first_, false);
  return first ? std::max(0.0, e) : e;
}

}  // namespace slamprep::sim
