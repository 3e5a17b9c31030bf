#include "algo/calibration/calibration_method.hpp"

#include <algorithm>

namespace slamprep::algo {
namespace {

struct MethodName {
  CalibrationMethod method;
  std::string_view name;
};

constexpr MethodName kMethodNames[] = {
    {CalibrationMethod::kDirect, "direct"},   {CalibrationMethod::kModel, "model"},
    {CalibrationMethod::kJoint, "joint"},     {CalibrationMethod::kCeres, "ceres"},
    {CalibrationMethod::kUmbmark, "umbmark"},
};

}  // namespace

const std::vector<CalibrationMethod>& allCalibrationMethods() {
  static const std::vector<CalibrationMethod> all = [] {
    std::vector<CalibrationMethod> v;
    for (const auto& m : kMethodNames) v.push_back(m.method);
    return v;
  }();
  return all;
}

std::string_view calibrationMethodName(CalibrationMethod method) {
  for (const auto& m : kMethodNames)
    if (m.method == method) return m.name;
  return "unknown";
}

std::optional<CalibrationMethod> parseCalibrationMethod(std::string_view name) {
  for (const auto& m : kMethodNames)
    if (m.name == name) return m.method;
  return std::nullopt;
}

std::vector<std::string> calibrationMethodNames() {
  std::vector<std::string> names;
  for (const auto& m : kMethodNames) names.emplace_back(m.name);
  return names;
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
