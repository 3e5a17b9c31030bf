#include "slamprep/algo/calibration/calibrate.hpp"

#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <numeric>
#include <string>

namespace slamprep::algo {
namespace {

// One fit on a subset of the intervals; `kept` names the subset (indices into all of them).
using IntervalFit = std::function<CalibrationRun(const std::vector<CalibrationInterval>& subset,
                                                 const std::vector<int>& kept)>;

// Closed-form joint fits by subset, so ceres starts from the joint fit of its own subset and
// joint runs once per subset when both are asked for.
using JointCache = std::map<std::vector<int>, JointResult>;

const JointResult& jointOn(JointCache& cache, const std::vector<CalibrationInterval>& subset,
                           const std::vector<int>& kept, const JointParams& params) {
  auto it = cache.find(kept);
  if (it == cache.end()) it = cache.emplace(kept, calibrateJoint(subset, params)).first;
  return it->second;
}

// A refit that fails where the fit before trimming stood (e.g. "channels swapped" from a few
// intervals) says more about the intervals than about the robot: the refusal says so.
std::string beforeDropping(const DiffDriveParams& g) {
  char text[240];
  std::snprintf(text, sizeof text,
                "; before dropping them the fit stood (r_L %.1f, r_R %.1f, b %.1f mm): the "
                "intervals disagree among themselves, they do not determine the geometry",
                1e3 * g.radius_left_m, 1e3 * g.radius_right_m, 1e3 * g.wheel_base_m);
  return text;
}

// Fit, screen every interval against the fit, refit on the kept ones; until the kept set repeats
// (robust_trim.hpp). Round 0 fits all intervals as given, so nothing dropped = the plain fit.
CalibrationRun robustFit(const std::vector<CalibrationInterval>& all, const TrimParams& params,
                         const IntervalFit& fit) {
  std::vector<int> kept(all.size());
  std::iota(kept.begin(), kept.end(), 0);
  CalibrationRun run = fit(all, kept);
  std::vector<TrimmedInterval> dropped;
  for (int round = 0; params.enabled && run.result.ok && round < params.max_rounds; ++round) {
    Screening screening = screenIntervals(all, run.result, params);
    if (screening.kept == kept) {  // converged: report the outliers scored by the final fit
      dropped = std::move(screening.dropped);
      break;
    }
    CalibrationRun refit = fit(selectIntervals(all, screening.kept), screening.kept);
    if (!refit.result.ok)
      refit.result.reason = "after dropping " + std::to_string(screening.dropped.size()) +
                            " outlier intervals: " + refit.result.reason +
                            beforeDropping(run.result.geometry);
    run = std::move(refit);
    kept = std::move(screening.kept);
    dropped = std::move(screening.dropped);
  }
  run.result.intervals_trimmed += static_cast<int>(all.size() - kept.size());
  if (static_cast<int>(dropped.size()) > params.report_worst) dropped.resize(params.report_worst);
  run.result.trimmed_worst = std::move(dropped);
  return run;
}

CalibrationRun makeRun(CalibrationMethod method, CalibrationResult result) {
  CalibrationRun run;
  run.method = method;
  run.result = std::move(result);
  return run;
}

CalibrationRun refused(CalibrationMethod method, std::string reason) {
  CalibrationRun run = makeRun(method, {});
  run.result.estimates_mount = estimatesMount(method);
  run.result.reason = std::move(reason);
  return run;
}

// The run of joint or ceres, with the sideslip when it was estimated (JointResult, CeresResult).
template <typename Result>
CalibrationRun withSideslip(CalibrationMethod method, const Result& r, bool estimated) {
  CalibrationRun run = makeRun(method, r);
  if (estimated && r.ok) {
    run.sideslip_s = r.sideslip_s;
    run.sideslip_sigma_s = r.sideslip_sigma_s;
  }
  return run;
}

CalibrationRun fromCeres(const CeresResult& r, const CeresParams& params) {
  CalibrationRun run = withSideslip(CalibrationMethod::kCeres, r, params.estimate_sideslip);
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
  return makeRun(CalibrationMethod::kUmbmark, calibrateUmbmark(input.umbmark_runs, params));
}

// The fit of one interval method on a subset of the intervals.
CalibrationRun fitMethod(CalibrationMethod method, const std::vector<CalibrationInterval>& subset,
                         const std::vector<int>& kept, const CalibrationInput& input,
                         const CalibrationParams& params, JointCache& joints) {
  switch (method) {
    case CalibrationMethod::kDirect: {
      DirectLinearParams direct = params.direct;
      direct.nominal = *input.nominal;
      return makeRun(method, calibrateDirectLinear(subset, direct));
    }
    case CalibrationMethod::kModel:
      return makeRun(method, calibrateModelBased(subset, params.model));
    case CalibrationMethod::kJoint:
      return withSideslip(method, jointOn(joints, subset, kept, params.joint),
                          params.joint.estimate_sideslip);
    case CalibrationMethod::kCeres: {
      const JointResult& start = jointOn(joints, subset, kept, params.joint);
      return fromCeres(calibrateCeres(subset, start, ceresParams(params)), params.ceres);
    }
    case CalibrationMethod::kUmbmark:
      break;
  }
  return refused(method, "not an interval method");
}

// An ok fit whose sigma is too large for the estimate to mean anything is refused, naming it.
CalibrationRun refuseUndetermined(CalibrationRun run, double max_relative_sigma) {
  if (!run.result.ok || !(max_relative_sigma > 0.0)) return run;
  const Eigen::VectorXd value = calibrationValues(run.result), sigma = run.result.sigma();
  for (int j = 0; j < 3 && j < sigma.size(); ++j) {  // r_L, r_R, b
    const double relative = sigma(j) / std::abs(value(j));
    if (!(relative > max_relative_sigma)) continue;
    char reason[240];
    std::snprintf(reason, sizeof reason,
                  "undetermined: %s = %.4g m with a 1-sigma of %.2g m (%.0f %%, limit %.0f %%): "
                  "the drive does not pin the geometry down (too short, too little turning)",
                  kCalibrationKeys[j], value(j), sigma(j), 100.0 * relative,
                  100.0 * max_relative_sigma);
    run.result.ok = false;
    run.result.reason = reason;
    return run;
  }
  return run;
}

CalibrationRun calibrateWith(CalibrationMethod method, const CalibrationInput& input,
                             CalibrationParams params, JointCache& joints) {
  params.joint.heading_loops = params.ceres.heading_loops = input.heading_loops;
  if (auto reason = missingInput(method, input)) return refused(method, std::move(*reason));
  if (method == CalibrationMethod::kUmbmark) return calibrateUmbmarkRuns(input, params);
  if (input.known_T_base_lidar && !estimatesMount(method)) {  // the mount given, not assumed
    CalibrationInput in_base = input;
    in_base.intervals = inBaseFrame(input.intervals, *input.known_T_base_lidar);
    in_base.known_T_base_lidar.reset();
    return calibrateWith(method, in_base, params, joints);
  }
  CalibrationRun run =
      robustFit(input.intervals, params.trim,
                [&](const std::vector<CalibrationInterval>& subset, const std::vector<int>& kept) {
                  return fitMethod(method, subset, kept, input, params, joints);
                });
  // The prior after the screening, which judges intervals by what they alone say.
  if (input.mount_prior) run.mount_prior = applyMountPrior(run.result, *input.mount_prior);
  return refuseUndetermined(std::move(run), params.max_relative_sigma);
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
  JointCache joints;
  return calibrateWith(method, input, params, joints);
}

std::vector<CalibrationRun> calibrate(const std::vector<CalibrationMethod>& methods,
                                      const CalibrationInput& input,
                                      const CalibrationParams& params) {
  std::vector<CalibrationRun> runs;
  JointCache joints;  // shared: joint runs once when both joint and ceres are asked for
  for (CalibrationMethod method : methods)
    runs.push_back(calibrateWith(method, input, params, joints));
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
