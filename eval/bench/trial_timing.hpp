#pragma once
// The wall-clock seconds of a trial's stages (timing/<id>.json, gathered into timing.json): kept
// apart from the trial result, whose bytes must depend on the spec alone.

#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

namespace slamprep::eval {

struct TrialTiming {
  double simulate_s = 0.0;                    ///< the simulation
  std::optional<double> motion_s;             ///< the calibration motion (when calibrating)
  std::map<std::string, double> calibration;  ///< per calibration method
  std::map<std::string, double> deskew;       ///< per de-skew method (its own time)

  bool operator==(const TrialTiming&) const = default;
};

/// The maps are written only when not empty.
void to_json(nlohmann::json& out, const TrialTiming& t);
void from_json(const nlohmann::json& in, TrialTiming& t);

}  // namespace slamprep::eval
