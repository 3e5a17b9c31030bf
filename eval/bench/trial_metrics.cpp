#include "slamprep/eval/bench/trial_metrics.hpp"

namespace slamprep::eval {
namespace {

// Record keys joined as flattenMetrics joins them.
std::string join(std::initializer_list<std::string_view> keys) {
  std::string path;
  for (const std::string_view k : keys) path.append(path.empty() ? "" : "/").append(k);
  return path;
}

std::string_view section(TrialSection s) {
  return nameOf(kTrialSectionKeys, s);
}

}  // namespace

std::string simMetric(SimField field) {
  return join({section(TrialSection::kSim), nameOf(kSimFieldKeys, field)});
}

std::string odometryMetric(OdometryGeometry geometry, OdometryField field) {
  return join({section(TrialSection::kOdometry), nameOf(kOdometryGeometryKeys, geometry),
               nameOf(kOdometryFieldKeys, field)});
}

std::string matchingMetric(MatchingField field) {
  const bool loops = field == MatchingField::kLoopsUsed ||
                     field == MatchingField::kLoopCandidates ||
                     field == MatchingField::kMaxLinkChange;
  if (!loops) return join({section(TrialSection::kMatching), nameOf(kMatchingFieldKeys, field)});
  return join({section(TrialSection::kMatching),
               nameOf(kMatchingFieldKeys, MatchingField::kLoopClosure),
               nameOf(kMatchingFieldKeys, field)});
}

std::string calibrationMetric(std::string_view method, CalibrationField field) {
  return join({section(TrialSection::kCalibration), method, nameOf(kCalibrationFieldKeys, field)});
}

std::string calibrationMetric(std::string_view method, CalibrationError kind,
                              CalibrationParam param) {
  return join({section(TrialSection::kCalibration), method, nameOf(kCalibrationErrorKeys, kind),
               nameOf(kCalibrationParamKeys, param)});
}

std::string calibrationMetric(std::string_view method, OdometryField field) {
  return join({section(TrialSection::kCalibration), method, nameOf(kOdometryFieldKeys, field)});
}

std::string deskewMetric(std::string_view method, DeskewField field) {
  return join({section(TrialSection::kDeskew), method, nameOf(kDeskewFieldKeys, field)});
}

std::string deskewMetric(std::string_view method, DeskewFigure figure) {
  return join({section(TrialSection::kDeskew), method, nameOf(kDeskewFigureKeys, figure)});
}

std::string deskewRefusalMetric(std::string_view method, std::string_view reason) {
  return join({section(TrialSection::kDeskew), method,
               nameOf(kDeskewFieldKeys, DeskewField::kRefusedByReason), reason});
}

std::string methodPrefix(TrialSection s, std::string_view method) {
  return join({section(s), method}) + "/";
}

std::string methodOfMetric(TrialSection s, std::string_view path) {
  const std::string prefix = std::string(section(s)) + "/";
  if (path.substr(0, prefix.size()) != prefix) return "";
  const std::string_view rest = path.substr(prefix.size());
  return std::string(rest.substr(0, rest.find('/')));
}

}  // namespace slamprep::eval
