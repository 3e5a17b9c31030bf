#pragma once
// Lidar motion-distortion removal (de-skew): every beam of a scan re-projected into the lidar frame
// at one reference time, with one interface for all methods (docs/design.md#de-skew-methods). One
// file per method family: deskew_reference.cpp (none, oracle), deskew_odometry.cpp (odom-linear,
// odom-quadratic), deskew_imu.cpp, deskew_const_velocity.cpp, deskew_vicp.cpp, deskew_odom_icp.cpp.
//
// Beam i is measured at t_i = t_first + i * time_increment from the lidar pose T_X_L(t_i); its
// de-skewed point is p_ref_i = T_X_L(t_ref)^-1 * T_X_L(t_i) * p_L_i. A method is a way to know
// T_Lref_L(t) = T_X_L(t_ref)^-1 T_X_L(t) over the scan.

#include <Eigen/Core>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "slamprep/algo/deskew/beam_transform.hpp"
#include "slamprep/algo/deskew/repack.hpp"
#include "slamprep/algo/matching/icp.hpp"
#include "slamprep/core/enum_names.hpp"
#include "slamprep/core/laser_scan.hpp"
#include "slamprep/core/samples.hpp"
#include "slamprep/core/se2.hpp"
#include "slamprep/core/time_series.hpp"

namespace slamprep::algo {

/// The methods, spelled in the CLI and JSON as deskewMethodName() returns.
enum class DeskewMethod {
  kNone,           ///< "none": raw points, the floor
  kOracle,         ///< "oracle": the true pose at every beam, the ceiling
  kConstVelocity,  ///< "const-velocity": the previous scan-to-scan motion (KISS-ICP)
  kVicp,           ///< "vicp": velocity estimated inside ICP, re-de-skewed until it settles
  kOdomLinear,     ///< "odom-linear": odometry interpolated at every beam
  kOdomQuadratic,  ///< "odom-quadratic": quadratic through p_s, p_m, p_e in k linear pieces
  kImu,            ///< "imu": rotation from the gyro, translation from odometry
  kOdomIcp,        ///< "odom-icp": odometry de-skew, then odometry error from ICP, iterated
};

inline constexpr auto kDeskewMethodNames = std::to_array<EnumName<DeskewMethod>>({
    {DeskewMethod::kNone, "none"},
    {DeskewMethod::kOracle, "oracle"},
    {DeskewMethod::kConstVelocity, "const-velocity"},
    {DeskewMethod::kVicp, "vicp"},
    {DeskewMethod::kOdomLinear, "odom-linear"},
    {DeskewMethod::kOdomQuadratic, "odom-quadratic"},
    {DeskewMethod::kImu, "imu"},
    {DeskewMethod::kOdomIcp, "odom-icp"},
});

/// Every method in the order above.
const std::vector<DeskewMethod>& allDeskewMethods();
std::string_view deskewMethodName(DeskewMethod method);
/// Inverse of deskewMethodName(); nullopt for an unknown name.
std::optional<DeskewMethod> parseDeskewMethod(std::string_view name);
/// Whether the method needs the previous scan (drive it with DeskewSequence).
bool deskewMethodUsesPreviousScan(DeskewMethod method);

/// A series a method needs beside the scans (the previous scan aside: every method but the first
/// scan's has one).
enum class DeskewInput {
  kGroundTruth,  ///< "ground truth": oracle
  kOdometry,     ///< "odometry": odom-linear, odom-quadratic, imu (translation), odom-icp
  kImu,          ///< "IMU samples": imu
};
inline constexpr auto kDeskewInputNames = std::to_array<EnumName<DeskewInput>>({
    {DeskewInput::kGroundTruth, "ground truth"},
    {DeskewInput::kOdometry, "odometry"},
    {DeskewInput::kImu, "IMU samples"},
});
std::string_view deskewInputName(DeskewInput input);
/// Which of those series a log has (not empty).
struct DeskewInputsGiven {
  bool groundtruth = false;
  bool odometry = false;
  bool imu = false;
};
/// The first series `method` needs that is not given, in the order above; nullopt when it has
/// them all. The one place that says which method needs what: deskew() refuses such a scan
/// (missing-input), and `slamprep deskew --method all` leaves the method out as not applicable.
std::optional<DeskewInput> deskewMissingInput(DeskewMethod method, DeskewInputsGiven given);

/// Which instant the de-skewed points describe.
enum class ReferenceTime { kFirst, kMiddle, kLast };
inline constexpr auto kReferenceTimeNames = std::to_array<EnumName<ReferenceTime>>({
    {ReferenceTime::kFirst, "first"},
    {ReferenceTime::kMiddle, "middle"},
    {ReferenceTime::kLast, "last"},
});
std::string_view referenceTimeName(ReferenceTime reference);
std::optional<ReferenceTime> parseReferenceTime(std::string_view name);

/// Why a method refused a scan: short fixed names (deskewRefusalName()) that can be counted.
enum class DeskewRefusal {
  kNone,             ///< "" : not refused
  kNoBeams,          ///< "no-beams": the scan is empty
  kNoBeamTimes,      ///< "no-beam-times": time_increment <= 0, beam times unknown
  kUnknownMethod,    ///< "unknown-method"
  kMissingInput,     ///< "missing-input": the method's input (odometry, IMU, truth) is absent
  kNotBracketed,     ///< "not-bracketed": odometry/IMU/truth do not cover the scan
  kSampleGap,        ///< "sample-gap": odometry/IMU has a gap inside the scan
  kBadPreviousScan,  ///< "bad-previous-scan": not earlier, or without beam times
  kMatchFailed,      ///< "match-failed": the scan-to-scan match did not converge
};
inline constexpr auto kDeskewRefusalNames = std::to_array<EnumName<DeskewRefusal>>({
    {DeskewRefusal::kNone, ""},
    {DeskewRefusal::kNoBeams, "no-beams"},
    {DeskewRefusal::kNoBeamTimes, "no-beam-times"},
    {DeskewRefusal::kUnknownMethod, "unknown-method"},
    {DeskewRefusal::kMissingInput, "missing-input"},
    {DeskewRefusal::kNotBracketed, "not-bracketed"},
    {DeskewRefusal::kSampleGap, "sample-gap"},
    {DeskewRefusal::kBadPreviousScan, "bad-previous-scan"},
    {DeskewRefusal::kMatchFailed, "match-failed"},
});
/// Every refusal reason but kNone, in the order above.
const std::vector<DeskewRefusal>& allDeskewRefusals();
std::string_view deskewRefusalName(DeskewRefusal reason);

/// What the stateful methods need from the previous scan (DeskewSequence fills this in).
struct PreviousScan {
  /// As measured. vicp and odom-icp re-de-skew it with every new estimate, so both scans of a
  /// match carry the same correction and its error does not feed back into the next scan.
  LaserScan scan;
  bool stamp_is_last_beam = false;
  /// Lidar twist (v_x, v_y, w) in its own frame, per second, from its scan-to-scan match.
  std::optional<Eigen::Vector3d> twist_lidar;
  /// odom-icp: the odometry error rate estimated with it (lidar frame, per second).
  std::optional<Eigen::Vector3d> odometry_error_per_s;
};

/// Everything a method may use besides the scan itself; an empty series means "not available".
/// Built once per log: DeskewSequence keeps `previous` up to date.
struct DeskewInputs {
  /// Odometry T_odom_base (odom-linear, odom-quadratic, imu, odom-icp; the guess for vicp).
  PoseSeries odometry;
  /// Gyro (imu).
  ImuLog imu;
  /// True T_world_base (oracle).
  PoseSeries groundtruth;
  /// The previous scan (const-velocity, vicp, odom-icp).
  std::optional<PreviousScan> previous;
  /// Lidar mount used with odometry and ground truth.
  SE2 T_base_lidar;
  /// The scans' stamps mark their last beam instead of their first (some drivers do this).
  bool stamp_is_last_beam = false;
  ReferenceTime reference = ReferenceTime::kFirst;
};

struct DeskewParams {
  /// odom-quadratic: number of linear pieces approximating the quadratic (the lecture's k).
  int quadratic_pieces = 4;
  /// Odometry (or IMU) samples farther apart than this inside a scan are a gap: refuse.
  double max_sample_gap_s = 0.1;
  /// vicp, odom-icp: de-skew-and-match rounds at most.
  int max_rounds = 10;
  /// vicp, odom-icp: stop when a round moves the scan-end pose by less than this ...
  double round_tolerance_m = 1e-4;
  /// ... and turns it by less than this (0.1 mm at 5 m).
  double round_tolerance_rad = 2e-5;
  /// Scan matcher for vicp and odom-icp (point-to-line).
  IcpParams icp;
  /// Also build the repacked LaserScan (costs an atan2 per beam).
  bool repack = true;
  /// How the corrected points are interpolated onto the grid (repack.hpp).
  RepackParams repacking;
};

struct DeskewResult {
  /// Every beam's point in the lidar frame at the reference time; nullopt for no return.
  std::vector<std::optional<Eigen::Vector2d>> p_ref;
  /// The points as a scan on the input's beam grid (repackOnGrid: each grid ray's range on the
  /// segment between the neighbouring points it crosses, +inf across depth jumps), stamped at
  /// the reference time with time_increment 0: all beams now describe one instant.
  LaserScan repacked;
  double first_beam_s = 0.0;  ///< time of beam 0
  double reference_s = 0.0;   ///< time the points describe
  /// Pose of the reference frame in the first-beam lidar frame (identity for kFirst).
  SE2 T_first_ref;
  /// The lidar motion the method assumed, seen from the reference frame: beam i was moved by
  /// poseAt(T_ref_lidar, t_i). Lets an evaluation split the error by its cause.
  Trajectory T_ref_lidar;
  /// vicp, odom-icp: the final scan-to-scan match (previous first beam <- this first beam).
  std::optional<IcpResult> match;
  /// vicp: the lidar twist it estimated (lidar frame, per second).
  std::optional<Eigen::Vector3d> twist_lidar;
  /// odom-icp: the odometry error rate it estimated (lidar frame, per second).
  std::optional<Eigen::Vector3d> odometry_error_per_s;
  int rounds = 0;  ///< vicp, odom-icp: de-skew-and-match rounds run
  bool ok = false;
  /// ok, but the beams were left as measured (method none, or no motion to de-skew with yet):
  /// they describe the sweep, not the reference instant.
  bool as_measured = false;
  DeskewRefusal refusal = DeskewRefusal::kNone;  ///< why it refused, as a countable name
  std::string reason;  ///< why it refused (ok = false), in words; else empty
  std::vector<std::string> warnings;
};

/// De-skews one scan. Refuses (ok = false, reason set, p_ref empty) when the method lacks its
/// input, the scan has time_increment <= 0, or odometry/IMU do not bracket the scan or have a gap.
DeskewResult deskew(DeskewMethod method, const LaserScan& scan, const DeskewInputs& inputs,
                    const DeskewParams& params);

/// Warns when `poses` do not bracket [first beam, last beam] of `scan`, and suggests the other
/// stamp convention when that one would be bracketed; nullopt when all is well.
std::optional<std::string> checkBracketing(const LaserScan& scan, bool stamp_is_last_beam,
                                           const PoseSeries& poses, std::string_view what);

/// The scan-to-scan motion as VICP estimates it: both scans de-skewed with one constant lidar
/// twist, the current matched against the previous (point-to-line), the twist re-estimated as
/// log(T_prev_cur) / dt, until it settles. For const-velocity's next prediction and for
/// `slamprep match`. `match` is T_prevfirst_curfirst.
struct MotionEstimate {
  bool ok = false;
  std::string reason;
  IcpResult match;
  Eigen::Vector3d twist_lidar = Eigen::Vector3d::Zero();
  int rounds = 0;
};
MotionEstimate estimateScanMotion(const PreviousScan& previous, const LaserScan& scan,
                                  bool stamp_is_last_beam, const Eigen::Vector3d& twist_guess,
                                  const DeskewParams& params);

/// Time of beam 0 under either stamp convention.
double firstBeamTime(const LaserScan& scan, bool stamp_is_last_beam);

}  // namespace slamprep::algo
