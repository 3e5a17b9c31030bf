#pragma once
// The odometry calibration methods by name: what the CLI, the suite files, the bench results and
// the calibration JSON call them, what each needs, and which result counts as the best.
//
// The best available result (one rule for calibrate, deskew --geometry, export and the bench):
// the first method with ok = true in the order ceres, joint, model, direct, umbmark. Ceres refines
// joint with every interval's noise model, joint adds the lidar mount to the model-based fit, the
// direct linear fit is a small-increment approximation and UMBmark is first order in the errors
// and cannot observe the mean wheel radius. The order is fixed, not driven by the reported
// sigmas: the methods' covariances come from different approximations and do not rank them.

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "slamprep/core/enum_names.hpp"

namespace slamprep::algo {

enum class CalibrationMethod {
  kDirect,   ///< "direct": direct linear map of odometry increments (direct_linear.hpp)
  kModel,    ///< "model": two-stage model-based least squares (model_based.hpp)
  kJoint,    ///< "joint": closed form with the lidar mount, Censi et al. (joint_censi.hpp)
  kCeres,    ///< "ceres": nonlinear refinement of joint (ceres_refine.hpp)
  kUmbmark,  ///< "umbmark": square runs, Borenstein & Feng (umbmark.hpp)
};
inline constexpr auto kCalibrationMethodNames = std::to_array<EnumName<CalibrationMethod>>({
    {CalibrationMethod::kDirect, "direct"},
    {CalibrationMethod::kModel, "model"},
    {CalibrationMethod::kJoint, "joint"},
    {CalibrationMethod::kCeres, "ceres"},
    {CalibrationMethod::kUmbmark, "umbmark"},
});

/// Every method in the order above: the order `calibrate --method all` runs and writes them.
const std::vector<CalibrationMethod>& allCalibrationMethods();
std::string_view calibrationMethodName(CalibrationMethod method);
/// Inverse of calibrationMethodName(); nullopt for an unknown name.
std::optional<CalibrationMethod> parseCalibrationMethod(std::string_view name);
/// The names of allCalibrationMethods(), for --help and CLI checks.
std::vector<std::string> calibrationMethodNames();
/// The names of `methods` joined with `separator` ("direct|model|..." for --help).
std::string joinCalibrationMethodNames(const std::vector<CalibrationMethod>& methods,
                                       std::string_view separator);

/// Whether the method calibrates from intervals (encoder steps plus measured lidar motion); all
/// but umbmark, which needs square runs instead.
bool isIntervalMethod(CalibrationMethod method);
/// The interval methods in the order above (what the bench can run).
std::vector<CalibrationMethod> intervalMethods();
/// Whether the method estimates the lidar mount T_base_lidar (joint, ceres).
bool estimatesMount(CalibrationMethod method);

/// The preference order of the rule in the header comment: ceres, joint, model, direct, umbmark.
const std::vector<CalibrationMethod>& calibrationPreference();
/// Position in calibrationPreference(): smaller is better.
int preferenceRank(CalibrationMethod method);

}  // namespace slamprep::algo
