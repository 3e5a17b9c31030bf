#include "slamprep/eval/bench/odometry_record.hpp"

#include "slamprep/eval/bench/record_fields.hpp"
#include "slamprep/eval/metrics/trajectory_error.hpp"

namespace slamprep::eval {

const std::optional<double>& OdometryRecord::operator[](OdometryField field) const {
  switch (field) {
    case OdometryField::kApeRmse:
      return ape_rmse_m;
    case OdometryField::kApeMax:
      return ape_max_m;
    case OdometryField::kRpeTransRmse:
      return rpe_trans_rmse_m;
    case OdometryField::kRpeRotRmse:
      break;
  }
  return rpe_rot_rmse_deg;
}

OdometryRecord odometryRecord(const PoseSeries& odom, const PoseSeries& truth) {
  const ApeResult ape = absolutePoseError(odom, truth, {.align = false, .align_origin = true});
  const RpeResult rpe = relativePoseError(odom, truth, {.delta = 1.0, .unit = DeltaUnit::kMeters});
  OdometryRecord r;
  if (ape.ok) {
    r.ape_rmse_m = ape.translation_m.rmse;
    r.ape_max_m = ape.translation_m.max;
  }
  if (rpe.ok) {
    r.rpe_trans_rmse_m = rpe.translation_m.rmse;
    r.rpe_rot_rmse_deg = rpe.rotation_deg.rmse;
  }
  return r;
}

void to_json(nlohmann::json& out, const OdometryRecord& r) {
  out = nlohmann::json::object();
  for (const auto& [field, key] : kOdometryFieldKeys)
    writeOptional(out, std::string(key), r[field]);
}

void from_json(const nlohmann::json& in, OdometryRecord& r) {
  r.ape_rmse_m = readOptional<double>(in, keyOf(kOdometryFieldKeys, OdometryField::kApeRmse));
  r.ape_max_m = readOptional<double>(in, keyOf(kOdometryFieldKeys, OdometryField::kApeMax));
  r.rpe_trans_rmse_m =
      readOptional<double>(in, keyOf(kOdometryFieldKeys, OdometryField::kRpeTransRmse));
  r.rpe_rot_rmse_deg =
      readOptional<double>(in, keyOf(kOdometryFieldKeys, OdometryField::kRpeRotRmse));
}

}  // namespace slamprep::eval
