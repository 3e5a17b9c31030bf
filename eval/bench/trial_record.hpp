#pragma once
// Everything one bench trial produces (trials/<id>.json, docs/results.md "Trial result"): one
// record per result, each with the one to_json/from_json that writes and reads its part of the
// JSON. The summary flattens that JSON generically (summary.hpp, flattenMetrics); code that reads
// a field does it through these structs or trial_metrics.hpp, never through a spelled-out path.

#include <array>
#include <cstddef>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "slamprep/core/enum_names.hpp"
#include "slamprep/eval/bench/artifacts_record.hpp"
#include "slamprep/eval/bench/calibration_record.hpp"
#include "slamprep/eval/bench/deskew_record.hpp"
#include "slamprep/eval/bench/matching_record.hpp"
#include "slamprep/eval/bench/odometry_record.hpp"
#include "slamprep/eval/bench/sim_record.hpp"
#include "slamprep/eval/bench/stamps_record.hpp"

namespace slamprep::eval {

/// The top-level keys of a trial result.
enum class TrialSection {
  kSim,
  kStamps,
  kFaults,
  kOdometry,
  kMatching,
  kCalibration,
  kDeskew,
  kArtifacts,
  kTrial
};

inline constexpr auto kTrialSectionKeys =
    std::to_array<EnumName<TrialSection>>({{TrialSection::kSim, "sim"},
                                           {TrialSection::kStamps, "stamps"},
                                           {TrialSection::kFaults, "faults"},
                                           {TrialSection::kOdometry, "odometry"},
                                           {TrialSection::kMatching, "matching"},
                                           {TrialSection::kCalibration, "calibration"},
                                           {TrialSection::kDeskew, "deskew"},
                                           {TrialSection::kArtifacts, "artifacts"},
                                           {TrialSection::kTrial, "trial"}});

/// The geometries whose raw odometry a trial scores ("odometry/<geometry>").
enum class OdometryGeometry { kNominal, kTrue };

inline constexpr auto kOdometryGeometryKeys = std::to_array<EnumName<OdometryGeometry>>(
    {{OdometryGeometry::kNominal, "nominal"}, {OdometryGeometry::kTrue, "true"}});

struct TrialRecord {
  SimRecord sim;                                         ///< what was simulated
  StampsRecord stamps;                                   ///< when a stream's stamps were moved
  std::map<std::string, std::size_t> faults;             ///< injected events per fault that was on
  OdometryRecord odometry_nominal;                       ///< raw odometry, nominal geometry
  OdometryRecord odometry_true;                          ///< raw odometry, true geometry
  std::optional<MatchingRecord> matching;                ///< when the motion is scan-matched
  std::map<std::string, CalibrationRecord> calibration;  ///< per calibration method
  std::map<std::string, DeskewRecord> deskew;            ///< per de-skew method
  std::optional<ArtifactsRecord> artifacts;              ///< the first trial's, for the plots
  nlohmann::json trial;  ///< the spec the runner stores with the result (specJson); null before

  bool operator==(const TrialRecord&) const = default;
};

/// Empty stamps, faults, calibration and deskew are not written, nor a null `trial`.
void to_json(nlohmann::json& out, const TrialRecord& r);
void from_json(const nlohmann::json& in, TrialRecord& r);

/// The key of a top-level section.
std::string sectionKey(TrialSection section);

/// The calibration records of a trial result by method; empty without any.
std::map<std::string, CalibrationRecord> calibrationRecords(const nlohmann::json& result);

}  // namespace slamprep::eval
