#include "slamprep/eval/bench/calibration_param.hpp"

#include <algorithm>

#include "slamprep/eval/bench/record_fields.hpp"

namespace slamprep::eval {

bool CalibrationParamValues::empty() const {
  return std::none_of(values.begin(), values.end(), [](const auto& v) { return v.has_value(); });
}

void to_json(nlohmann::json& out, const CalibrationParamValues& v) {
  out = nlohmann::json::object();
  for (const CalibrationParam p : kCalibrationParams)
    writeOptional(out, keyOf(kCalibrationParamKeys, p), v[p]);
}

void from_json(const nlohmann::json& in, CalibrationParamValues& v) {
  for (const CalibrationParam p : kCalibrationParams)
    v[p] = readOptional<double>(in, keyOf(kCalibrationParamKeys, p));
}

}  // namespace slamprep::eval
