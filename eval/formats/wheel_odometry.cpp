#include "slamprep/eval/formats/wheel_odometry.hpp"

#include "slamprep/core/error.hpp"
#include "slamprep/core/odometry.hpp"
#include "slamprep/eval/formats/import.hpp"

namespace slamprep::eval {

OdometryEncoders odometryEncoders(const Dataset& d, const std::string& source,
                                  const std::optional<DiffDriveParams>& nominal) {
  OdometryEncoders out{source, d.encoders, d.info.ticks_per_revolution, SE2(), std::nullopt};
  if (d.encoders.size() < 2 && d.odom_nominal.size() >= 2) {
    out.derived_with = nominal.value_or(d.info.nominal_geometry);
    out.encoders = encodersFromPoses(d.odom_nominal, *out.derived_with, out.ticks_per_revolution);
  }
  if (!out.encoders.empty())
    out.T_odom_base0 = d.odom_nominal.at(out.encoders.front().stamp_s).value_or(SE2());
  return out;
}

PoseSeries integrateOdometry(const OdometryEncoders& e, const DiffDriveParams& geometry) {
  if (e.encoders.size() < 2)
    throw InputError(e.source,
                     "neither encoder ticks nor odometry poses (two or more): no odometry to "
                     "integrate with the calibrated geometry");
  return integrateEncoders(e.encoders, geometry, e.ticks_per_revolution, e.T_odom_base0);
}

PoseSeries calibratedOdometry(const Dataset& dataset, const std::string& source,
                              const DiffDriveParams& geometry,
                              const std::optional<DiffDriveParams>& nominal) {
  return integrateOdometry(odometryEncoders(dataset, source, nominal), geometry);
}

}  // namespace slamprep::eval
