#pragma once
// The six calibration parameters a trial scores (wheel radii, wheel base, lidar mount), their
// keys in a trial result and in the summary's consistency, and one optional value per parameter.

#include <array>
#include <cstddef>
#include <nlohmann/json.hpp>
#include <optional>

#include "slamprep/core/enum_names.hpp"

namespace slamprep::eval {

enum class CalibrationParam { kRL, kRR, kB, kMountX, kMountY, kMountYaw };

/// Every parameter, in the order tables and figures list them.
inline constexpr std::array kCalibrationParams = {
    CalibrationParam::kRL,     CalibrationParam::kRR,     CalibrationParam::kB,
    CalibrationParam::kMountX, CalibrationParam::kMountY, CalibrationParam::kMountYaw};

/// Key of a parameter's error and sigma in a trial result, its unit in the name: % of the true
/// value for the wheels, mm and degrees for the mount ("calibration/<method>/abs_error/<key>").
inline constexpr auto kCalibrationParamKeys =
    std::to_array<EnumName<CalibrationParam>>({{CalibrationParam::kRL, "r_L_pct"},
                                               {CalibrationParam::kRR, "r_R_pct"},
                                               {CalibrationParam::kB, "b_pct"},
                                               {CalibrationParam::kMountX, "lidar_x_mm"},
                                               {CalibrationParam::kMountY, "lidar_y_mm"},
                                               {CalibrationParam::kMountYaw, "lidar_yaw_deg"}});

/// Name of a parameter in the summary's consistency keys ("calibration/<method>/consistency/
/// <name>/bias").
inline constexpr auto kCalibrationParamNames =
    std::to_array<EnumName<CalibrationParam>>({{CalibrationParam::kRL, "r_L"},
                                               {CalibrationParam::kRR, "r_R"},
                                               {CalibrationParam::kB, "b"},
                                               {CalibrationParam::kMountX, "lidar_x"},
                                               {CalibrationParam::kMountY, "lidar_y"},
                                               {CalibrationParam::kMountYaw, "lidar_yaw"}});

/// One optional value per parameter (an error or a sigma), in the unit its key names.
struct CalibrationParamValues {
  std::array<std::optional<double>, kCalibrationParams.size()> values;  ///< by CalibrationParam

  std::optional<double>& operator[](CalibrationParam p) {
    return values[static_cast<std::size_t>(p)];
  }
  const std::optional<double>& operator[](CalibrationParam p) const {
    return values[static_cast<std::size_t>(p)];
  }
  /// No parameter has a value (the object is not written).
  bool empty() const;
  bool operator==(const CalibrationParamValues&) const = default;
};

/// {"<key>": value} for the parameters with a value.
void to_json(nlohmann::json& out, const CalibrationParamValues& v);
/// The parameters whose key is present; other keys are not read.
void from_json(const nlohmann::json& in, CalibrationParamValues& v);

}  // namespace slamprep::eval
