#pragma once
// One calibration method in a trial ("calibration/<method>" of a trial result): its estimate's
// error against the simulated truth per parameter, the sigma it reported, whether the truth is
// inside 3 sigma, and how its geometry dead-reckons; or why it refused.

#include <array>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "slamprep/algo/calibration/calibrate.hpp"
#include "slamprep/core/dataset.hpp"
#include "slamprep/core/enum_names.hpp"
#include "slamprep/eval/bench/calibration_param.hpp"
#include "slamprep/eval/bench/odometry_record.hpp"

namespace slamprep::eval {

/// The scalar fields of a CalibrationRecord, by the JSON key they are written under.
enum class CalibrationField {
  kOk,
  kReason,
  kRefusalNamesFault,
  kConditionNumber,
  kNees,
  kInside3Sigma,
  kDrift,
  kSideslip
};

inline constexpr auto kCalibrationFieldKeys = std::to_array<EnumName<CalibrationField>>(
    {{CalibrationField::kOk, "ok"},
     {CalibrationField::kReason, "reason"},
     {CalibrationField::kRefusalNamesFault, "refusal_names_fault"},
     {CalibrationField::kConditionNumber, "condition_number"},
     {CalibrationField::kNees, "nees"},
     {CalibrationField::kInside3Sigma, "inside_3sigma"},
     {CalibrationField::kDrift, "drift_m"},
     {CalibrationField::kSideslip, "sideslip_ms"}});

/// The per-parameter objects of a CalibrationRecord: abs_error/<key>, signed_error/<key>, ...
enum class CalibrationError { kAbs, kSigned, kSigma };

inline constexpr auto kCalibrationErrorKeys =
    std::to_array<EnumName<CalibrationError>>({{CalibrationError::kAbs, "abs_error"},
                                               {CalibrationError::kSigned, "signed_error"},
                                               {CalibrationError::kSigma, "sigma"}});

/// The sideslip term (calibration_sideslip), in milliseconds.
struct SideslipRecord {
  double value = 0.0;  ///< k [ms]
  double sigma = 0.0;  ///< its 1-sigma [ms]

  bool operator==(const SideslipRecord&) const = default;
};

struct CalibrationRecord {
  bool ok = false;                          ///< the method gave an estimate
  std::string reason;                       ///< why it refused (written only when !ok)
  std::optional<bool> refusal_names_fault;  ///< refused with faults on: the reason names one
  std::optional<double> condition_number;   ///< of the fit (when ok)
  CalibrationParamValues abs_error;         ///< |estimate - truth| per estimated parameter
  CalibrationParamValues signed_error;      ///< estimate - truth, same units
  CalibrationParamValues sigma;             ///< the 1-sigma the method reported, same units
  std::optional<double> nees;               ///< NEES with the full covariance (SI units)
  std::optional<bool> inside_3sigma;        ///< every parameter's |error| <= 3 sigma
  std::optional<double> drift_m;            ///< final position error of its odometry [m]
  OdometryRecord odometry;                  ///< its odometry against the truth (same object)
  std::optional<SideslipRecord> sideslip;   ///< with calibration_sideslip

  /// The per-parameter values `kind` names.
  const CalibrationParamValues& operator[](CalibrationError kind) const;
  bool operator==(const CalibrationRecord&) const = default;
};

/// Scores `run` against the truth of `dataset` (which must have a true geometry).
CalibrationRecord calibrationRecord(const Dataset& dataset, const algo::CalibrationRun& run);

void to_json(nlohmann::json& out, const CalibrationRecord& r);
/// Lenient about what a refusal or a method without sigma leaves out; "ok" is required.
void from_json(const nlohmann::json& in, CalibrationRecord& r);

}  // namespace slamprep::eval
