#pragma once
// How well scan matching found the lidar's motion in a trial ("matching" of a trial result):
// every scan-to-scan match against the true lidar motion, and what loop closure did.

#include <array>
#include <cstddef>
#include <nlohmann/json.hpp>
#include <optional>

#include "slamprep/core/dataset.hpp"
#include "slamprep/core/enum_names.hpp"
#include "slamprep/eval/pipeline/calibration_run.hpp"

namespace slamprep::eval {

/// The fields of a MatchingRecord and its LoopClosureRecord, by their JSON key.
enum class MatchingField {
  kPairs,
  kConvergedFraction,
  kTransErrorMean,
  kTransErrorRmse,
  kRotErrorMean,
  kRotErrorRmse,
  kLoopClosure,
  kLoopsUsed,
  kLoopCandidates,
  kMaxLinkChange
};

inline constexpr auto kMatchingFieldKeys = std::to_array<EnumName<MatchingField>>(
    {{MatchingField::kPairs, "pairs"},
     {MatchingField::kConvergedFraction, "converged_fraction"},
     {MatchingField::kTransErrorMean, "trans_error_m_mean"},
     {MatchingField::kTransErrorRmse, "trans_error_m_rmse"},
     {MatchingField::kRotErrorMean, "rot_error_deg_mean"},
     {MatchingField::kRotErrorRmse, "rot_error_deg_rmse"},
     {MatchingField::kLoopClosure, "loop_closure"},
     {MatchingField::kLoopsUsed, "used"},
     {MatchingField::kLoopCandidates, "candidates"},
     {MatchingField::kMaxLinkChange, "max_link_change_deg"}});

/// The error of the converged matches with truth at both ends.
struct MatchErrorRecord {
  double trans_error_m_mean = 0.0;  ///< mean |translation error| [m]
  double trans_error_m_rmse = 0.0;  ///< RMS translation error [m]
  double rot_error_deg_mean = 0.0;  ///< mean |rotation error| [deg]
  double rot_error_deg_rmse = 0.0;  ///< RMS rotation error [deg]

  bool operator==(const MatchErrorRecord&) const = default;
};

/// What loop closure did to the chains (calibration_loop_closure).
struct LoopClosureRecord {
  int used = 0;                      ///< direct matches that corrected the chains
  int candidates = 0;                ///< pairs matched directly (used + refused)
  double max_link_change_deg = 0.0;  ///< the largest heading change of one link

  bool operator==(const LoopClosureRecord&) const = default;
};

struct MatchingRecord {
  std::size_t pairs = 0;                          ///< matches attempted
  double converged_fraction = 0.0;                ///< of them converged (0 without pairs)
  std::optional<MatchErrorRecord> error;          ///< nullopt when nothing could be compared
  std::optional<LoopClosureRecord> loop_closure;  ///< with loop closure

  bool operator==(const MatchingRecord&) const = default;
};

/// The matches of `motion` against the true lidar motion of `dataset`.
MatchingRecord matchingRecord(const Dataset& dataset, const CalibrationMotion& motion);

/// The error's fields sit beside pairs and converged_fraction, not in an object of their own.
void to_json(nlohmann::json& out, const MatchingRecord& r);
void from_json(const nlohmann::json& in, MatchingRecord& r);

}  // namespace slamprep::eval
