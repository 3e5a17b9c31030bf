#include "eval/pipeline/dataset_deskew.hpp"

#include <chrono>

#include "core/odometry.hpp"

namespace slamprep::eval {
namespace {

using BeamPoints = std::vector<std::optional<Eigen::Vector2d>>;

// The true undistorted points moved from the first-beam frame to the result's reference frame,
// using the TRUE motion between the two instants (not the method's estimate).
BeamPoints truthAtReference(const Dataset& dataset, const ScanRecord& record,
                            const algo::DeskewResult& result) {
  if (result.reference_s == result.first_beam_s) return record.p_ref_true;
  const SE2& l = dataset.info.T_base_lidar;
  const auto T_w_first = dataset.groundtruth.at(result.first_beam_s);
  const auto T_w_ref = dataset.groundtruth.at(result.reference_s);
  if (!T_w_first || !T_w_ref) return {};
  const SE2 T_ref_first = between(*T_w_ref * l, *T_w_first * l);
  BeamPoints out(record.p_ref_true.size());
  for (std::size_t i = 0; i < out.size(); ++i)
    if (record.p_ref_true[i]) out[i] = T_ref_first * *record.p_ref_true[i];
  return out;
}

// Appends |corrected - true| of every beam that has both.
void collectErrors(const BeamPoints& corrected, const BeamPoints& truth, std::vector<double>& out) {
  if (corrected.size() != truth.size()) return;
  for (std::size_t i = 0; i < truth.size(); ++i)
    if (corrected[i] && truth[i]) out.push_back((*corrected[i] - *truth[i]).norm());
}

}  // namespace

DatasetDeskewOptions nominalDeskewOptions(const Dataset& dataset) {
  DatasetDeskewOptions options;
  options.geometry = dataset.info.nominal_geometry;
  options.T_base_lidar = dataset.info.T_base_lidar;
  return options;
}

DatasetDeskew deskewDataset(const Dataset& dataset, algo::DeskewMethod method,
                            const DatasetDeskewOptions& options) {
  const PoseSeries odometry =
      integrateEncoders(dataset.encoders, options.geometry, dataset.info.ticks_per_revolution);
  algo::DeskewSequence sequence(method, options.params);
  DatasetDeskew out;
  std::vector<double> errors_m;
  for (const ScanRecord& record : dataset.scans) {
    algo::DeskewInput input;
    input.scan = &record.scan;
    input.reference = options.reference;
    input.odometry = &odometry;
    input.T_base_lidar = options.T_base_lidar;
    input.imu = &dataset.imu;
    input.oracle = dataset.groundtruth.empty() ? nullptr : &dataset.groundtruth;
    const auto start = std::chrono::steady_clock::now();
    algo::DeskewResult result = sequence.next(input);
    out.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (!result.ok && out.refused++ == 0) out.first_reason = result.reason;
    if (result.ok && !record.p_ref_true.empty())
      collectErrors(result.p_ref, truthAtReference(dataset, record, result), errors_m);
    out.scans.push_back(std::move(result));
  }
  if (!errors_m.empty()) out.error_m = summarize(std::move(errors_m));
  return out;
}

std::vector<Points2> correctedPoints(const DatasetDeskew& deskewed) {
  std::vector<Points2> out;
  out.reserve(deskewed.scans.size());
  for (const auto& scan : deskewed.scans) {
    Points2 points;
    for (const auto& p : scan.p_ref)
      if (p) points.push_back(*p);
    out.push_back(std::move(points));
  }
  return out;
}

}  // namespace slamprep::eval
