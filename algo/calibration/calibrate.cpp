#include "algo/calibration/calibrate.hpp"

namespace slamprep::algo {
namespace {

CalibrationRun refused(CalibrationMethod method, std::string reason) {
  CalibrationRun run{method, {}, std::nullopt, 0.0};
  run.result.estimates_mount = estimatesMount(method);
  run.result.reason = std::move(reason);
  return run;
}

CalibrationRun fromCeres(const CeresResult& r, const CeresParams& params) {
  CalibrationRun run{CalibrationMethod::kCeres, r, std::nullopt, 0.0};
  if (params.estimate_time_offset && r.ok) {
    run.time_offset_s = r.time_offset_s;
    run.time_offset_sigma_s = r.time_offset_sigma_s;
  }
  return run;
}

CeresParams ceresParams(const CalibrationParams& params) {
  CeresParams ceres = params.ceres;
  ceres.start = params.joint;
  return ceres;
}

CalibrationRun calibrateUmbmarkRuns(const CalibrationInput& input, const CalibrationParams& p) {
  UmbmarkParams params = p.umbmark;
  if (input.nominal) params.nominal = *input.nominal;
  return {CalibrationMethod::kUmbmark, calibrateUmbmark(input.umbmark_runs, params), std::nullopt,
          0.0};
}

}  // namespace

std::optional<std::string> missingInput(CalibrationMethod method, const CalibrationInput& input) {
  if (method == CalibrationMethod::kDirect && !input.nominal)
    return "needs the nominal geometry of a dataset (give DATASET with --tuples)";
  if (method == CalibrationMethod::kUmbmark && input.umbmark_runs.empty())
    return "no UMBmark square runs: simulate worlds/scenarios/umbmark_cw.yaml and "
           "umbmark_ccw.yaml and pass them (DATASET or --square DIR)";
  return std::nullopt;
}

CalibrationRun calibrate(CalibrationMethod method, const CalibrationInput& input,
                         const CalibrationParams& params) {
  if (auto reason = missingInput(method, input)) return refused(method, std::move(*reason));
  const auto& intervals = input.intervals;
  switch (method) {
    case CalibrationMethod::kDirect: {
      DirectLinearParams direct = params.direct;
      direct.nominal = *input.nominal;
      return {method, calibrateDirectLinear(intervals, direct), std::nullopt, 0.0};
    }
    case CalibrationMethod::kModel:
      return {method, calibrateModelBased(intervals, params.model), std::nullopt, 0.0};
    case CalibrationMethod::kJoint:
      return {method, calibrateJoint(intervals, params.joint), std::nullopt, 0.0};
    case CalibrationMethod::kCeres:
      return fromCeres(calibrateCeres(intervals, ceresParams(params)), params.ceres);
    case CalibrationMethod::kUmbmark:
      return calibrateUmbmarkRuns(input, params);
  }
  return refused(method, "unknown method");
}

std::vector<CalibrationRun> calibrate(const std::vector<CalibrationMethod>& methods,
                                      const CalibrationInput& input,
                                      const CalibrationParams& params) {
  std::vector<CalibrationRun> runs;
  std::optional<JointResult> joint;
  for (CalibrationMethod method : methods) {
    const bool joint_based =
        method == CalibrationMethod::kJoint || method == CalibrationMethod::kCeres;
    if (!joint_based) {
      runs.push_back(calibrate(method, input, params));
      continue;
    }
    if (!joint) joint = calibrateJoint(input.intervals, params.joint);
    if (method == CalibrationMethod::kJoint)
      runs.push_back({method, *joint, std::nullopt, 0.0});
    else
      runs.push_back(
          fromCeres(calibrateCeres(input.intervals, *joint, ceresParams(params)), params.ceres));
  }
  return runs;
}

const CalibrationRun* bestRun(const std::vector<CalibrationRun>& runs) {
  const CalibrationRun* best = nullptr;
  for (const CalibrationRun& run : runs)
    if (run.result.ok && (!best || preferenceRank(run.method) < preferenceRank(best->method)))
      best = &run;
  return best;
}

}  // namespace slamprep::algo
