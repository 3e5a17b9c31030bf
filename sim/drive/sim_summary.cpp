// summarize: counts, distance and odometry drift of a simulated dataset (declared in
// simulator.hpp; the drift is eval::odometryDrift, the one the bench reports).

#include <cmath>

#include "slamprep/core/odometry.hpp"
#include "slamprep/sim/drive/simulator.hpp"

namespace slamprep::sim {

SimSummary summarize(const Dataset& dataset, SimMode mode) {
  SimSummary s;
  s.mode = mode;
  const PoseSeries& gt = dataset.groundtruth;
  if (!gt.empty()) {
    s.duration_s = gt.backStamp() - gt.frontStamp();
    s.physics_steps = gt.size() - 1;
  }
  for (std::size_t k = 1; k < gt.size(); ++k) {
    s.distance_m += (gt[k].value.translation() - gt[k - 1].value.translation()).norm();
    s.rotation_rad += std::abs(normalizeAngle(gt[k].value.yaw - gt[k - 1].value.yaw));
  }
  s.scans = dataset.scans.size();
  for (const ScanRecord& record : dataset.scans) {
    s.beams += record.scan.size();
    for (std::size_t i = 0; i < record.scan.size(); ++i) s.returns += record.scan.valid(i) ? 1 : 0;
  }
  const int ticks = dataset.info.ticks_per_revolution;
  s.drift_nominal = eval::odometryDrift(
      integrateEncoders(dataset.encoders, dataset.info.nominal_geometry, ticks), gt);
  if (dataset.info.true_geometry) {
    s.drift_true = eval::odometryDrift(
        integrateEncoders(dataset.encoders, *dataset.info.true_geometry, ticks), gt);
  }
  return s;
}

}  // namespace slamprep::sim
