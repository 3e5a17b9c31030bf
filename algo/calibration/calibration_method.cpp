#include "slamprep/algo/calibration/calibration_method.hpp"

#include <algorithm>

namespace slamprep::algo {
const std::vector<CalibrationMethod>& allCalibrationMethods() {
  static const std::vector<CalibrationMethod> all = [] {
    std::vector<CalibrationMethod> v;
    for (const auto& [method, name] : kCalibrationMethodNames) v.push_back(method);
    return v;
  }();
  return all;
}

std::string_view calibrationMethodName(CalibrationMethod method) {
  return nameOf(kCalibrationMethodNames, method);
}

std::optional<CalibrationMethod> parseCalibrationMethod(std::string_view name) {
  return findName(kCalibrationMethodNames, name);
}

std::vector<std::string> calibrationMethodNames() {
  return namesOf(kCalibrationMethodNames);
}

std::string joinCalibrationMethodNames(const std::vector<CalibrationMethod>& methods,
                                       std::string_view separator) {
  std::string out;
  for (CalibrationMethod m : methods) {
    if (!out.empty()) out += separator;
    out += calibrationMethodName(m);
  }
  return out;
}

bool isIntervalMethod(CalibrationMethod method) {
  return method != CalibrationMethod::kUmbmark;
}

std::vector<CalibrationMethod> intervalMethods() {
  std::vector<CalibrationMethod> out;
  for (CalibrationMethod m : allCalibrationMethods())
    if (isIntervalMethod(m)) out.push_back(m);
  return out;
}

bool estimatesMount(CalibrationMethod method) {
  return method == CalibrationMethod::kJoint || method == CalibrationMethod::kCeres;
}

const std::vector<CalibrationMethod>& calibrationPreference() {
  static const std::vector<CalibrationMethod> order = {
      CalibrationMethod::kCeres, CalibrationMethod::kJoint, CalibrationMethod::kModel,
      CalibrationMethod::kDirect, CalibrationMethod::kUmbmark};
  return order;
}

int preferenceRank(CalibrationMethod method) {
  const auto& order = calibrationPreference();
  return static_cast<int>(std::find(order.begin(), order.end(), method) - order.begin());
}

}  // namespace slamprep::algo
