#include "slamprep/algo/calibration/calibration_json.hpp"

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <tuple>
#include <utility>

#include "slamprep/algo/agreement/agreement_report.hpp"
#include "slamprep/core/atomic_file.hpp"
#include "slamprep/core/error.hpp"
#include "slamprep/core/input_file.hpp"
#include "slamprep/core/json_input.hpp"

namespace slamprep::algo {
namespace {

using nlohmann::json;

json geometryJson(const DiffDriveParams& g) {
  return {{"r_L", g.radius_left_m}, {"r_R", g.radius_right_m}, {"b", g.wheel_base_m}};
}

json errorJson(const HeldOutError& e) {
  return {{"trans_m", e.trans_m}, {"rot_deg", e.rot_deg}};
}

json validationJson(const ValidationFigures& v) {
  json j = {
      {"fraction", v.fraction}, {"raw", errorJson(v.raw)}, {"calibrated", errorJson(v.calibrated)}};
  if (v.calibrated_wheels) j["calibrated_wheels"] = errorJson(*v.calibrated_wheels);
  return j;
}

// The six values of kCalibrationKeys as an object.
json valuesJson(const Eigen::VectorXd& v) {
  json j = json::object();
  for (int i = 0; i < v.size(); ++i) j[kCalibrationKeys[i]] = v(i);
  return j;
}

json mountPriorJson(const MountPriorUse& u) {
  const SE2& m = u.prior.T_base_lidar;
  return {{"from", u.prior.from},
          {"lidar_x", m.x},
          {"lidar_y", m.y},
          {"lidar_yaw", m.yaw},
          {"sigma_xy_m", u.prior.sigma_xy_m},
          {"sigma_yaw_rad", u.prior.sigma_yaw_rad},
          {"chi2", u.chi2},
          {"applied", u.applied},
          {"without_prior", valuesJson(u.without_prior)},
          {"without_prior_sigma", valuesJson(u.without_prior_sigma)}};
}

// The sigmas the sandwich raised, by parameter (sandwichFloor); empty where it raised none.
json sandwichJson(const CalibrationResult& r) {
  json raised = json::object();
  for (std::size_t i = 0; i < r.sigma_sandwich_factors.size(); ++i)
    if (r.sigma_sandwich_factors[i] > 1.0)
      raised[kCalibrationKeys[i]] = r.sigma_sandwich_factors[i];
  return raised;
}

json runJson(const CalibrationRun& run, const std::optional<Eigen::VectorXd>& truth) {
  const CalibrationResult& r = run.result;
  json j = {{"method", calibrationMethodName(run.method)}, {"ok", r.ok}, {"reason", r.reason}};
  const Eigen::VectorXd v = calibrationValues(r);
  const bool has_sigma = r.covariance.size() > 0;
  const Eigen::VectorXd s = r.sigma();
  json sigma = json::object(), error = json::object();
  for (int i = 0; i < v.size(); ++i) {
    j[kCalibrationKeys[i]] = r.ok ? json(v(i)) : json(nullptr);
    sigma[kCalibrationKeys[i]] = r.ok && has_sigma ? json(s(i)) : json(nullptr);
    if (truth) error[kCalibrationKeys[i]] = r.ok ? json(calibrationError(v, *truth, i)) : nullptr;
  }
  j["sigma"] = sigma;
  if (truth) j["error"] = error;
  j["condition_number"] =
      std::isfinite(r.condition_number) ? json(r.condition_number) : json(nullptr);
  j["intervals"] = r.intervals_used;
  j["intervals_trimmed"] = r.intervals_trimmed;
  json worst = json::array();
  for (const TrimmedInterval& t : r.trimmed_worst)
    worst.push_back(
        {{"t0", t.t0_s}, {"t1", t.t1_s}, {"reason", t.reason}, {"residual", t.residual_sigmas}});
  j["trimmed_worst"] = worst;
  if (r.rotation_heteroscedasticity > kTurnHeteroscedasticityMinStatistic)  // a finding only
    j["rotation_heteroscedasticity"] = r.rotation_heteroscedasticity;
  if (const json raised = sandwichJson(r); !raised.empty()) j["sigma_sandwich"] = raised;
  if (run.time_offset_s)
    j["time_offset_s"] = {{"value", *run.time_offset_s}, {"sigma", run.time_offset_sigma_s}};
  if (run.sideslip_s)
    j["sideslip_s"] = {{"value", *run.sideslip_s}, {"sigma", run.sideslip_sigma_s}};
  if (run.mount_prior) j["mount_prior"] = mountPriorJson(*run.mount_prior);
  if (const auto& nominal = run.relative_to_odometry) {
    j["relative_to_odometry"] = geometryJson(*nominal);
    if (r.ok)
      j["scale"] = {{"r_L", r.geometry.radius_left_m / nominal->radius_left_m},
                    {"r_R", r.geometry.radius_right_m / nominal->radius_right_m},
                    {"b", r.geometry.wheel_base_m / nominal->wheel_base_m}};
    j["meaning"] = odometryRelativeMeaning(*nominal);
  }
  return j;
}

// One method object: the run's keys, plus "flags", "validation" and "against_nominal" when there
// are any (a run without a nominal geometry, --tuples alone, writes none of them).
json methodJson(const MethodReport& m, const std::optional<Eigen::VectorXd>& truth) {
  json j = runJson(m.run, truth);
  if (!m.flags.empty()) {
    json flags = json::array();
    for (const NominalFlag& f : m.flags)
      flags.push_back({{"param", f.param}, {"ratio", f.ratio}, {"likely_cause", f.likely_cause}});
    j["flags"] = flags;
  }
  if (m.validation) j["validation"] = validationJson(*m.validation);
  if (const auto& t = m.against_nominal)
    j["against_nominal"] = {{"chi2", t->chi2},
                            {"dof", t->dof},
                            {"p", t->p},
                            {"z", {{"r_L", t->z(0)}, {"r_R", t->z(1)}, {"b", t->z(2)}}},
                            {"shows_nominal_wrong", t->shows_nominal_wrong}};
  return j;
}

json methodsJson(const std::vector<MethodReport>& methods,
                 const std::optional<CalibrationTruth>& truth) {
  std::optional<Eigen::VectorXd> truth_values;
  if (truth) truth_values = truth->values();
  json out = json::array();
  for (const MethodReport& m : methods) out.push_back(methodJson(m, truth_values));
  return out;
}

json agreementOf(const RecordingReport& r) {
  // agreementJson is an ordered_json; this file writes nlohmann::json.
  return json::parse(agreementJson(*r.agreement, r.encoders_from).dump());
}

json consistencyJson(const std::vector<MethodConsistency>& consistency) {
  json out = json::object();
  for (const MethodConsistency& c : consistency) {
    json params = json::object();
    for (const ParameterConsistency& p : c.params)
      params[p.param] = {{"chi2_dof", std::isfinite(p.chi2_dof) ? json(p.chi2_dof) : json(nullptr)},
                         {"n", p.n}};
    out[std::string(calibrationMethodName(c.method))] = params;
  }
  return out;
}

// {METHOD: {"recordings": [...], "beats_raw": {"trans", "rot", "scored"}}}.
json leaveOneOutJson(const std::vector<LeaveOneOutMethod>& methods) {
  json out = json::object();
  for (const LeaveOneOutMethod& m : methods) {
    json recordings = json::array();
    for (const LeaveOneOutScore& s : m.recordings) {
      json entry = {{"dataset", s.dataset}, {"others", s.others}};
      if (s.figures) {
        entry.update(validationJson(*s.figures));
        entry.erase("fraction");  // the whole recording
      } else {
        entry["note"] = s.note;
      }
      recordings.push_back(entry);
    }
    const BeatsRaw b = beatsRaw(m);
    out[std::string(calibrationMethodName(m.method))] = {
        {"recordings", recordings},
        {"beats_raw", {{"trans", b.trans}, {"rot", b.rot}, {"scored", b.scored}}}};
  }
  return out;
}

// Reads one entry; `where` is "FILE: [i]".
class EntryReader {
 public:
  EntryReader(const json& entry, std::string where) : e_(entry), where_(std::move(where)) {}

  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    throw InputError(key.empty() ? where_ : where_ + "." + key, what);
  }

  CalibrationMethod method() const {
    if (!e_.contains("method") || !e_["method"].is_string())
      fail("method", "missing or not a string");
    return parseName(kCalibrationMethodNames, e_["method"].get<std::string>(), "method",
                     where_ + ".method");
  }

  bool ok() const {
    if (!e_.contains("ok") || !e_["ok"].is_boolean()) fail("ok", "must be true or false");
    return e_["ok"].get<bool>();
  }

  double finite(const char* key) const {
    if (!e_.contains(key) || !e_[key].is_number()) fail(key, "missing or not a number");
    const double v = e_[key].get<double>();
    if (!std::isfinite(v)) fail(key, "must be finite");
    return v;
  }

  double positive(const char* key) const {
    const double v = finite(key);
    if (!(v > 0.0)) fail(key, "must be a number > 0");
    return v;
  }

  std::string reason() const {
    return e_.contains("reason") && e_["reason"].is_string() ? e_["reason"].get<std::string>()
                                                             : std::string();
  }

  // The 1-sigmas as a diagonal covariance; empty unless every parameter has one.
  Eigen::MatrixXd covariance(int n) const {
    if (!e_.contains("sigma") || !e_["sigma"].is_object()) return {};
    const json& s = e_["sigma"];
    Eigen::VectorXd variance(n);
    for (int i = 0; i < n; ++i) {
      const char* key = kCalibrationKeys[i];
      if (!s.contains(key) || !s[key].is_number()) return {};
      const double sigma = s[key].get<double>();
      if (!std::isfinite(sigma) || sigma < 0.0) fail(std::string("sigma.") + key, "must be >= 0");
      variance(i) = sigma * sigma;
    }
    return variance.asDiagonal();
  }

  int count(const char* key) const {
    if (!e_.contains(key)) return 0;
    if (!e_[key].is_number_integer() || e_[key].get<long long>() < 0)
      fail(key, "must be an integer >= 0");
    return e_[key].get<int>();
  }

  std::vector<TrimmedInterval> trimmedWorst() const {
    std::vector<TrimmedInterval> out;
    if (!e_.contains("trimmed_worst")) return out;
    const json& list = e_["trimmed_worst"];
    if (!list.is_array()) fail("trimmed_worst", "must be an array");
    for (std::size_t i = 0; i < list.size(); ++i) {
      const EntryReader item(list[i], where_ + ".trimmed_worst[" + std::to_string(i) + "]");
      if (!list[i].is_object()) item.fail("", "not an object");
      out.push_back({item.finite("t0"), item.finite("t1"), item.reason(), item.finite("residual")});
    }
    return out;
  }

  std::optional<DiffDriveParams> relativeToOdometry() const {
    if (!e_.contains("relative_to_odometry")) return std::nullopt;
    const json& g = e_["relative_to_odometry"];
    const EntryReader item(g, where_ + ".relative_to_odometry");
    if (!g.is_object()) item.fail("", "not an object");
    return DiffDriveParams{item.positive("r_L"), item.positive("r_R"), item.positive("b")};
  }

  // {"value", "sigma"} of an extra estimate (time_offset_s, sideslip_s), when written.
  std::optional<std::pair<double, double>> extra(const char* key) const {
    if (!e_.contains(key)) return std::nullopt;
    const EntryReader item(e_[key], where_ + "." + key);
    if (!e_[key].is_object()) item.fail("", "not an object");
    return std::pair{item.finite("value"), item.finite("sigma")};
  }

  std::vector<double> sandwichFactors(int params) const {
    if (!e_.contains("sigma_sandwich")) return {};
    const EntryReader item(e_["sigma_sandwich"], where_ + ".sigma_sandwich");
    if (!e_["sigma_sandwich"].is_object()) item.fail("", "not an object");
    std::vector<double> f(params, 1.0);
    for (int i = 0; i < params; ++i)
      if (e_["sigma_sandwich"].contains(kCalibrationKeys[i]))
        f[i] = item.positive(kCalibrationKeys[i]);
    return f;
  }

  CalibrationRun run() const {
    CalibrationRun run;
    run.method = method();
    CalibrationResult& r = run.result;
    r.ok = ok();
    r.reason = reason();
    r.estimates_mount = estimatesMount(run.method);
    r.intervals_trimmed = count("intervals_trimmed");
    r.trimmed_worst = trimmedWorst();
    run.relative_to_odometry = relativeToOdometry();
    if (!r.ok) return run;
    r.geometry = {positive("r_L"), positive("r_R"), positive("b")};  // braces: left to right
    if (r.estimates_mount)
      r.T_base_lidar = SE2{finite("lidar_x"), finite("lidar_y"), finite("lidar_yaw")};
    r.covariance = covariance(r.estimates_mount ? 6 : 3);
    const bool has_condition =
        e_.contains("condition_number") && e_["condition_number"].is_number();
    r.condition_number = has_condition ? e_["condition_number"].get<double>()
                                       : std::numeric_limits<double>::infinity();
    if (e_.contains("intervals") && e_["intervals"].is_number_integer())
      r.intervals_used = e_["intervals"].get<int>();
    if (const auto offset = extra("time_offset_s"))
      std::tie(run.time_offset_s, run.time_offset_sigma_s) = *offset;
    if (const auto k = extra("sideslip_s")) std::tie(run.sideslip_s, run.sideslip_sigma_s) = *k;
    if (e_.contains("rotation_heteroscedasticity"))
      r.rotation_heteroscedasticity = finite("rotation_heteroscedasticity");
    r.sigma_sandwich_factors = sandwichFactors(r.estimates_mount ? 6 : 3);
    return run;
  }

 private:
  const json& e_;
  std::string where_;
};

}  // namespace

Eigen::VectorXd CalibrationTruth::values() const {
  Eigen::VectorXd v(6);
  v << geometry.radius_left_m, geometry.radius_right_m, geometry.wheel_base_m, T_base_lidar.x,
      T_base_lidar.y, T_base_lidar.yaw;
  return v;
}

double calibrationError(const Eigen::VectorXd& estimate, const Eigen::VectorXd& truth, int i) {
  const double e = estimate(i) - truth(i);
  return i == 5 ? normalizeAngle(e) : e;
}

std::string odometryRelativeMeaning(const DiffDriveParams& g) {
  return "the log has no encoder ticks: wheel increments were derived from its odometry poses "
         "with the nominal geometry r_L " +
         json(g.radius_left_m).dump() + " m, r_R " + json(g.radius_right_m).dump() + " m, b " +
         json(g.wheel_base_m).dump() +
         " m, so r_L, r_R, b are relative to the log's own odometry geometry: scale = estimate / "
         "nominal is the factor by which the geometry the robot's odometry used must be "
         "multiplied (1 = the odometry was already right)";
}

std::string formatCalibrateJson(const CalibrateReport& report) {
  if (report.recordings.size() == 1) {
    const RecordingReport& only = report.recordings.front();
    json methods = methodsJson(only.methods, only.truth);
    if (only.agreement)
      for (json& m : methods) {
        m["sensor_agreement"] = agreementOf(only);
        m["clock_sync_s"] = only.clock_sync_s;
      }
    return methods.dump(2) + "\n";
  }
  json recordings = json::array();
  for (const RecordingReport& r : report.recordings) {
    json entry = {{"dataset", r.dataset}, {"methods", methodsJson(r.methods, r.truth)}};
    if (r.agreement) {
      entry["sensor_agreement"] = agreementOf(r);
      entry["clock_sync_s"] = r.clock_sync_s;
    }
    recordings.push_back(entry);
  }
  json out = {{"recordings", recordings},
              {"combined", methodsJson(report.combined, report.combined_truth)},
              {"consistency", consistencyJson(report.consistency)}};
  if (!report.leave_one_out.empty()) out["leave_one_out"] = leaveOneOutJson(report.leave_one_out);
  return out.dump(2) + "\n";
}

std::string formatCalibrationJson(const std::vector<CalibrationRun>& runs,
                                  const std::optional<CalibrationTruth>& truth) {
  RecordingReport recording{"", {}, truth, std::nullopt, ""};
  for (const CalibrationRun& run : runs)
    recording.methods.push_back({run, {}, std::nullopt, std::nullopt});
  CalibrateReport report;
  report.recordings = {recording};
  return formatCalibrateJson(report);
}

void writeCalibrationJson(const std::filesystem::path& path,
                          const std::vector<CalibrationRun>& runs,
                          const std::optional<CalibrationTruth>& truth) {
  writeFileAtomic(path, formatCalibrationJson(runs, truth));
}

void writeCalibrateJson(const std::filesystem::path& path, const CalibrateReport& report) {
  writeFileAtomic(path, formatCalibrateJson(report));
}

CalibrationRun CalibrationFile::requireBest() const {
  const CalibrationRun* run = best();
  if (!run) throw InputError(source, "no calibration result with ok = true");
  return *run;
}

CalibrationFile parseCalibrationJson(std::string_view text, const std::string& source) {
  json j = parseJsonInput(text, source);  // nesting and repeated keys checked first
  std::string source_prefix = source + ": ";
  if (j.is_object() && j.contains("combined")) {  // several recordings: their combination
    j = json(j["combined"]);
    source_prefix = source + ": combined";
  }
  if (j.is_object()) j = json::array({j});
  if (!j.is_array())
    throw InputError(source, "expected the array `slamprep calibrate --json` writes");
  CalibrationFile file{source, {}};
  for (std::size_t i = 0; i < j.size(); ++i) {
    const std::string where = source_prefix + "[" + std::to_string(i) + "]";
    if (!j[i].is_object()) throw InputError(where, "not an object");
    file.runs.push_back(EntryReader(j[i], where).run());
  }
  return file;
}

CalibrationFile readCalibrationJson(const std::filesystem::path& path) {
  return parseCalibrationJson(readInputFile(path, "calibration file", kMaxRecordFileBytes),
                              path.string());
}

}  // namespace slamprep::algo
