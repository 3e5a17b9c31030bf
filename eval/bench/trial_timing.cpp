#include "slamprep/eval/bench/trial_timing.hpp"

#include "slamprep/eval/bench/record_fields.hpp"

namespace slamprep::eval {

void to_json(nlohmann::json& out, const TrialTiming& t) {
  out = {{"simulate_s", t.simulate_s}};
  writeOptional(out, "motion_s", t.motion_s);
  if (!t.calibration.empty()) out["calibration"] = t.calibration;
  if (!t.deskew.empty()) out["deskew"] = t.deskew;
}

void from_json(const nlohmann::json& in, TrialTiming& t) {
  t.simulate_s = readField<double>(in, "simulate_s");
  t.motion_s = readOptional<double>(in, "motion_s");
  t.calibration = in.value("calibration", std::map<std::string, double>{});
  t.deskew = in.value("deskew", std::map<std::string, double>{});
}

}  // namespace slamprep::eval
