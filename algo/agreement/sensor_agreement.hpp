#pragma once
// Sensors checked against each other (docs/design.md "Sensor agreement"). Wheels, gyro, the
// robot's own odometry topic and the scan-matched trajectory each say how far the robot turned.
// Their turns are compared over sliding windows and over the whole recording; a window where two
// of them disagree beyond what their model allows is reported with its likely cause, so that a
// lifted robot, wheel slip or a heading taken from the gyro is seen before it becomes a confident
// but wrong calibration.
//
// Models, per window w (length window_s, one starting every step_s), of what source B turned
// from what source A says:
//   A the wheels, B a rotation reference (gyro, odometry topic, scans):
//     dB_w = a dphi_R,w - c dphi_L,w  (+ g dt_w for a gyro's bias),                    (Eq. 1)
//     a = r_R / b, c = r_L / b: every wheel geometry is such a pair, so what Eq. 1 leaves
//     over is what no wheel geometry explains;
//   two rotation references A and B:
//     dB_w = s dA_w  (+ g dt_w where one is the gyro) (+ k ds_w where one is the odometry
//     topic, ds_w its signed travel: unequal radii in its geometry turn it as it drives). (Eq. 2)
// Fit: least absolute deviations first (a block of faulty windows drags least squares, not it),
// then the windows beyond outlier_sigmas robust sigmas (1.4826 MAD over all windows) dropped and
// least squares on the rest, repeated until the kept set repeats; b's clock delay behind a's is
// the one of a grid that fits best. A window disagrees when
// its residual exceeds max(disagreement_sigmas sigma, disagreement_floor_rad); overlapping
// disagreeing windows merge into one span.

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "slamprep/core/diff_drive.hpp"
#include "slamprep/core/heading.hpp"

namespace slamprep::algo {

/// Cumulative wheel angles (rad) and the geometry the robot believes.
struct WheelTrack {
  TimeSeries<Eigen::Vector2d> phi_rad;  ///< (left, right), cumulative
  DiffDriveParams nominal;
  /// Where the wheel angles came from: "ticks", "joint_states" or "odometry_poses" (derived from
  /// the odometry topic's poses: then they are that topic, not independent wheels).
  std::string from = "ticks";
};

/// What a recording holds that says how the robot turned; any may be missing.
struct RotationSources {
  std::optional<WheelTrack> wheels;
  std::optional<HeadingSeries> gyro;
  std::optional<HeadingSeries> odometry;  ///< the odometry topic, where the wheels are not it
  /// The scan-matched heading, in pieces: chained scan-to-scan matches break where a match
  /// failed, and nothing is known of the turn across a break.
  std::vector<HeadingSeries> scans;
  /// The odometry topic's signed travel (poseTravel), for Eq. 2's k: a topic integrated from
  /// wheels with unequal nominal radii turns in proportion to it.
  std::optional<TimeSeries<double>> odometry_travel;
};

struct AgreementParams {
  double window_s = 5.0;
  double step_s = 1.0;
  /// A gyro with two samples farther apart than this inside a window says nothing of it (its
  /// rate is unknown in between; poses and wheel angles keep what was turned across a gap).
  double max_gap_s = 0.5;
  double outlier_sigmas = 5.0;
  double disagreement_sigmas = 5.0;
  /// No window disagrees by less than this: below it, wheel-geometry fits and matcher noise
  /// cannot be told apart from a fault.
  double disagreement_floor_rad = 5.0 * 3.14159265358979323846 / 180.0;
  /// Robust sigma floor (noise-free simulated data has MAD ~ 0).
  double min_sigma_rad = 1e-4;
  /// The delay between two sources' clocks is searched over +-max_lag_s in lag_step_s (0: not
  /// searched): a real robot's odometry and scans are stamped by different clocks and paths,
  /// and a 0.1 s delay reads as 6 degrees per window in a 1 rad/s turn.
  double max_lag_s = 0.5;
  double lag_step_s = 0.01;
  /// A delay is kept where its fit's capped RMS (each window's residual capped at outlier_sigmas
  /// robust sigmas of the best fit) is below this fraction of no delay's,
  double lag_gain = 0.8;
  /// or where the windows show it beyond chance: n ln(rms_0^2 / rms^2) over this (chi^2 with one
  /// degree of freedom at p = 0.001), n the windows counted once per window_s (they overlap).
  /// A long recording shows a small delay the gain alone would miss (50 ms on ACES, 0.85x).
  double lag_significance = 10.83;
};

/// How much one source turned over the span every source covers (SensorAgreement::shared_from_s
/// .. shared_to_s), so that the sources' figures compare.
struct SourceTurning {
  std::string name;
  double from_s = 0.0, to_s = 0.0;  ///< what the source itself covers
  double net_rad = 0.0;             ///< last minus first heading over the shared span
  double absolute_rad = 0.0;        ///< sum of |turn| over steps of step_s, likewise
};

/// A span of merged disagreeing windows.
struct Disagreement {
  double t0_s = 0.0, t1_s = 0.0;
  double turn_a_rad = 0.0;        ///< what source a turned over the span
  double turn_b_rad = 0.0;        ///< what source b turned
  double max_residual_rad = 0.0;  ///< the largest window residual of Eq. 1 / Eq. 2 inside
  std::string likely_cause;
};

/// Two sources compared (a is the one modelled: the wheels where they take part).
struct PairAgreement {
  std::string a, b;
  std::string model;        ///< "wheels" (Eq. 1) or "scale" (Eq. 2)
  std::size_t windows = 0;  ///< windows both cover
  std::size_t kept = 0;     ///< windows the final fit kept
  double lag_s = 0.0;       ///< b's stamps lag a's by this (b read at t + lag_s)
  double scale = 1.0;       ///< over the kept windows: sum |dA| / sum |dB| (wheels: nominal)
  double bias_radps = 0.0;  ///< g of Eq. 1 / Eq. 2 (0 without a gyro)
  /// k of Eq. 2 where one source is the odometry topic: what it turns per metre of its travel.
  std::optional<double> travel_rad_per_m;
  /// Eq. 1: (a, c) = (r_R / b, r_L / b), and b with the nominal radii: (r_L + r_R) / (a + c).
  std::optional<Eigen::Vector2d> wheel_ratios;
  std::optional<double> effective_wheel_base_m;
  double rms_residual_rad = 0.0;  ///< over the kept windows
  double sigma_rad = 0.0;         ///< robust sigma of the residuals
  std::vector<Disagreement> disagreements;
};

struct SensorAgreement {
  AgreementParams params;
  std::vector<SourceTurning> sources;
  double shared_from_s = 0.0, shared_to_s = 0.0;  ///< the span every source covers
  std::vector<PairAgreement> pairs;
  /// Recording-level conclusions in words (a gyro-heading odometry, ...).
  std::vector<std::string> findings;
  /// The wheel angles were derived from an odometry topic that turns as the gyro does (scale
  /// within 1 %, under 0.5 deg RMS per window): if its heading is the gyro's, their rotation is
  /// too, and no wheel base can be calibrated from them (one of the findings).
  bool wheels_follow_gyro = false;

  const PairAgreement* pair(const std::string& a, const std::string& b) const;
  /// The wheels and the gyro disagree beyond every wheel geometry somewhere: what calibrate
  /// refuses on.
  const PairAgreement* wheelsGyroConflict() const;
  /// Without a gyro, the wheels and the scan-matched motion disagree somewhere: what calibrate
  /// flags (and leaves out with --exclude-disagreement), since nothing tells which is wrong.
  const PairAgreement* wheelsScansConflict() const;
};

/// Compares every two sources present (nothing when fewer than two).
SensorAgreement compareSensors(const RotationSources& sources, const AgreementParams& params = {});

/// The wheels' heading with a geometry: (r_R phi_R - r_L phi_L) / b.
HeadingSeries wheelHeading(const WheelTrack& wheels, const DiffDriveParams& geometry);

}  // namespace slamprep::algo
