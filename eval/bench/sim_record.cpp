#include "slamprep/eval/bench/sim_record.hpp"

#include "slamprep/eval/bench/record_fields.hpp"

namespace slamprep::eval {
namespace {

std::string key(SimField field) {
  return keyOf(kSimFieldKeys, field);
}

}  // namespace

SimRecord simRecord(const sim::SimSummary& s) {
  return {.duration_s = s.duration_s,
          .scans = s.scans,
          .beams = s.beams,
          .distance_m = s.distance_m,
          .turned_rad = s.rotation_rad,
          .mean_abs_yaw_rate_radps = s.duration_s > 0 ? s.rotation_rad / s.duration_s : 0.0,
          .mean_speed_mps = s.duration_s > 0 ? s.distance_m / s.duration_s : 0.0,
          .drift_nominal_m = s.drift_nominal.final_position_error_m,
          .drift_true_m = s.drift_true.final_position_error_m};
}

void to_json(nlohmann::json& out, const SimRecord& r) {
  out = {{key(SimField::kDuration), r.duration_s},
         {key(SimField::kScans), r.scans},
         {key(SimField::kBeams), r.beams},
         {key(SimField::kDistance), r.distance_m},
         {key(SimField::kTurned), r.turned_rad},
         {key(SimField::kMeanAbsYawRate), r.mean_abs_yaw_rate_radps},
         {key(SimField::kMeanSpeed), r.mean_speed_mps},
         {key(SimField::kDriftNominal), r.drift_nominal_m},
         {key(SimField::kDriftTrue), r.drift_true_m}};
}

void from_json(const nlohmann::json& in, SimRecord& r) {
  r.duration_s = readField<double>(in, key(SimField::kDuration));
  r.scans = readField<std::size_t>(in, key(SimField::kScans));
  r.beams = readField<std::size_t>(in, key(SimField::kBeams));
  r.distance_m = readField<double>(in, key(SimField::kDistance));
  r.turned_rad = readField<double>(in, key(SimField::kTurned));
  r.mean_abs_yaw_rate_radps = readField<double>(in, key(SimField::kMeanAbsYawRate));
  r.mean_speed_mps = readField<double>(in, key(SimField::kMeanSpeed));
  r.drift_nominal_m = readField<double>(in, key(SimField::kDriftNominal));
  r.drift_true_m = readField<double>(in, key(SimField::kDriftTrue));
}

}  // namespace slamprep::eval
