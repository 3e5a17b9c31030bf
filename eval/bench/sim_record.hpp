#pragma once
// What the simulator drove in a trial ("sim" of a trial result): time, scans, path, and how far
// dead reckoning drifted with the nominal and the true geometry.

#include <array>
#include <cstddef>
#include <nlohmann/json.hpp>

#include "slamprep/core/enum_names.hpp"
#include "slamprep/sim/drive/simulator.hpp"

namespace slamprep::eval {

/// The fields of a SimRecord, by the JSON key they are written under.
enum class SimField {
  kDuration,
  kScans,
  kBeams,
  kDistance,
  kTurned,
  kMeanAbsYawRate,
  kMeanSpeed,
  kDriftNominal,
  kDriftTrue
};

inline constexpr auto kSimFieldKeys =
    std::to_array<EnumName<SimField>>({{SimField::kDuration, "duration_s"},
                                       {SimField::kScans, "scans"},
                                       {SimField::kBeams, "beams"},
                                       {SimField::kDistance, "distance_m"},
                                       {SimField::kTurned, "turned_rad"},
                                       {SimField::kMeanAbsYawRate, "mean_abs_yaw_rate_radps"},
                                       {SimField::kMeanSpeed, "mean_speed_mps"},
                                       {SimField::kDriftNominal, "drift_nominal_m"},
                                       {SimField::kDriftTrue, "drift_true_m"}});

struct SimRecord {
  double duration_s = 0.0;               ///< simulated time
  std::size_t scans = 0;                 ///< complete scans
  std::size_t beams = 0;                 ///< beams cast in complete scans
  double distance_m = 0.0;               ///< length of the true path
  double turned_rad = 0.0;               ///< total |yaw| turned
  double mean_abs_yaw_rate_radps = 0.0;  ///< turned_rad / duration_s (0 without time)
  double mean_speed_mps = 0.0;           ///< distance_m / duration_s (0 without time)
  double drift_nominal_m = 0.0;          ///< final position error of the nominal-geometry odometry
  double drift_true_m = 0.0;  ///< ... of the true-geometry odometry (slip and ticks only)

  bool operator==(const SimRecord&) const = default;
};

/// The record of a simulation's summary.
SimRecord simRecord(const sim::SimSummary& summary);

void to_json(nlohmann::json& out, const SimRecord& r);
void from_json(const nlohmann::json& in, SimRecord& r);

}  // namespace slamprep::eval
