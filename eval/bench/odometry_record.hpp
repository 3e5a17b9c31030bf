#pragma once
// Dead reckoning against the truth in a trial result, as evo computes it: APE after putting the
// first poses together (--align_origin), RPE per metre driven. A trial records it for the
// nominal, the true and every calibrated geometry.

#include <array>
#include <nlohmann/json.hpp>
#include <optional>

#include "slamprep/core/enum_names.hpp"
#include "slamprep/core/time_series.hpp"

namespace slamprep::eval {

/// The figures of an OdometryRecord, by the JSON key they are written under.
enum class OdometryField { kApeRmse, kApeMax, kRpeTransRmse, kRpeRotRmse };

inline constexpr auto kOdometryFieldKeys =
    std::to_array<EnumName<OdometryField>>({{OdometryField::kApeRmse, "ape_rmse_m"},
                                            {OdometryField::kApeMax, "ape_max_m"},
                                            {OdometryField::kRpeTransRmse, "rpe_trans_rmse_m"},
                                            {OdometryField::kRpeRotRmse, "rpe_rot_rmse_deg"}});

struct OdometryRecord {
  std::optional<double> ape_rmse_m;        ///< APE translation RMSE [m]; with ape_max_m or none
  std::optional<double> ape_max_m;         ///< APE translation max [m]
  std::optional<double> rpe_trans_rmse_m;  ///< RPE over 1 m of path, translation RMSE [m]
  std::optional<double> rpe_rot_rmse_deg;  ///< RPE over 1 m of path, rotation RMSE [deg]

  /// The figure `field` names.
  const std::optional<double>& operator[](OdometryField field) const;
  bool operator==(const OdometryRecord&) const = default;
};

/// `odom` against `truth`; a figure evo could not compute (too short, no overlap) is left out.
OdometryRecord odometryRecord(const PoseSeries& odom, const PoseSeries& truth);

/// {figures that were computed} ({} when none).
void to_json(nlohmann::json& out, const OdometryRecord& r);
void from_json(const nlohmann::json& in, OdometryRecord& r);

}  // namespace slamprep::eval
