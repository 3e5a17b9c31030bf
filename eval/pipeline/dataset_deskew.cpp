#include "slamprep/eval/pipeline/dataset_deskew.hpp"

#include <algorithm>
#include <chrono>

#include "slamprep/algo/deskew/repack.hpp"
#include "slamprep/core/odometry.hpp"
#include "slamprep/core/order_statistics.hpp"
#include "slamprep/eval/metrics/deskew_error.hpp"

namespace slamprep::eval {
namespace {

/// A gap is a dropout when it is long for the stream that has it: the configured limit, or 2.5
/// of the slower stream's median periods where that is longer (a real robot's 5 Hz odometry
/// has 0.2 s between samples, each of which the 0.1 s limit refused).
double sampleGapLimit(const algo::DeskewInputs& in, double limit_s) {
  std::vector<double> odometry, imu;
  for (const auto& s : in.odometry.samples()) odometry.push_back(s.stamp_s);
  for (const ImuSample& s : in.imu) imu.push_back(s.stamp_s);
  return std::max({limit_s, 2.5 * medianSpacing(odometry), 2.5 * medianSpacing(imu)});
}

// The true undistorted points moved from the first-beam frame to the result's reference frame,
// using the TRUE motion between the two instants (not the method's estimate).
BeamPoints truthAtReference(const Dataset& dataset, const ScanRecord& record,
                            const algo::DeskewResult& result) {
  if (result.reference_s == result.first_beam_s) return record.p_ref_true;
  const SE2& l = dataset.info.trueMount();
  const auto T_w_first = dataset.groundtruth.at(result.first_beam_s);
  const auto T_w_ref = dataset.groundtruth.at(result.reference_s);
  if (!T_w_first || !T_w_ref) return {};
  const SE2 T_ref_first = between(*T_w_ref * l, *T_w_first * l);
  BeamPoints out(record.p_ref_true.size());
  for (std::size_t i = 0; i < out.size(); ++i)
    if (record.p_ref_true[i]) out[i] = T_ref_first * *record.p_ref_true[i];
  return out;
}

// Delta_i = T_ref_beam_est * T_ref_beam_true^-1 for every beam (eval::beamPoseError): what the
// method assumed against the true lidar motion, both seen from the reference frame.
std::vector<SE2> beamPoseErrors(const Dataset& dataset, const ScanRecord& record,
                                const algo::DeskewResult& result) {
  const SE2& l = dataset.info.trueMount();
  const auto T_w_ref = dataset.groundtruth.at(result.reference_s);
  if (!T_w_ref) return {};
  const SE2 T_lidarref_w = (*T_w_ref * l).inverse();
  std::vector<SE2> out(record.scan.size());
  for (std::size_t i = 0; i < out.size(); ++i) {
    const double t_i = result.first_beam_s + i * record.scan.time_increment_s;
    const auto T_w_beam = dataset.groundtruth.at(t_i);
    if (!T_w_beam) return {};
    const SE2 T_ref_beam_true = T_lidarref_w * (*T_w_beam * l);
    out[i] = beamPoseError(algo::poseAt(result.T_ref_lidar, t_i), T_ref_beam_true);
  }
  return out;
}

// Per-beam errors of all scans, pooled before summarising.
struct PooledErrors {
  std::vector<double> total_m, rotation_m, translation_m, repacked_m;
  std::vector<double> as_measured_m;  ///< refused scans left as measured: method none's errors
  std::size_t repacked_lost = 0;
  double max_residual_m = 0.0;
  bool split = true;  ///< every compared scan had its pose errors

  void add(const DeskewErrorResult& e) {
    total_m.insert(total_m.end(), e.errors_m.begin(), e.errors_m.end());
    split = split && e.has_split;
    if (!e.has_split) return;
    rotation_m.insert(rotation_m.end(), e.rotation_errors_m.begin(), e.rotation_errors_m.end());
    translation_m.insert(translation_m.end(), e.translation_errors_m.begin(),
                         e.translation_errors_m.end());
    max_residual_m = std::max(max_residual_m, e.max_split_residual_m);
  }
};

void measure(const Dataset& dataset, const ScanRecord& record, const algo::DeskewResult& result,
             const algo::RepackParams& repacking, PooledErrors& pooled) {
  const BeamPoints truth = truthAtReference(dataset, record, result);
  if (truth.size() != result.p_ref.size()) return;
  const DeskewErrorResult e =
      deskewError(result.p_ref, truth, beamPoseErrors(dataset, record, result));
  if (e.ok) pooled.add(e);
  if (result.repacked.size() != truth.size()) return;  // not repacked
  // The truth through the same repacking: the surface each grid ray crosses, exact for flat
  // walls, so what remains is the de-skew error carried onto the grid.
  const LaserScan truth_repacked = algo::repackOnGrid(record.scan, truth, repacking).scan;
  const RepackedErrorResult r = repackedError(result.repacked.ranges_m, truth_repacked.ranges_m);
  pooled.repacked_m.insert(pooled.repacked_m.end(), r.errors_m.begin(), r.errors_m.end());
  pooled.repacked_lost += r.lost;
}

/// What method none reads of `inputs`: no series, the stamps' convention and the reference.
algo::DeskewInputs noneInputs(const algo::DeskewInputs& inputs) {
  algo::DeskewInputs out;
  out.T_base_lidar = inputs.T_base_lidar;
  out.stamp_is_last_beam = inputs.stamp_is_last_beam;
  out.reference = inputs.reference;
  return out;
}

/// A refused scan as `match` keeps it: method none's points, measured as none's are.
void measureAsMeasured(const Dataset& dataset, const ScanRecord& record,
                       const algo::DeskewInputs& none_inputs, algo::DeskewParams params,
                       PooledErrors& pooled) {
  params.repack = false;  // the repacked figures cover de-skewed scans only
  const algo::DeskewResult none =
      algo::deskew(algo::DeskewMethod::kNone, record.scan, none_inputs, params);
  if (!none.ok) return;  // no beams or beam times: none refuses it too
  PooledErrors scan;
  measure(dataset, record, none, params.repacking, scan);
  pooled.as_measured_m.insert(pooled.as_measured_m.end(), scan.total_m.begin(), scan.total_m.end());
}

/// The de-skewed scans' errors and the refused scans' as measured, over every measured scan.
std::optional<ErrorStats> fallbackErrors(const PooledErrors& pooled) {
  if (pooled.total_m.empty() && pooled.as_measured_m.empty()) return std::nullopt;
  std::vector<double> all = pooled.total_m;
  all.insert(all.end(), pooled.as_measured_m.begin(), pooled.as_measured_m.end());
  return summarize(std::move(all));
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
  algo::DeskewInputs inputs;
  inputs.odometry = options.odometry ? *options.odometry
                                     : integrateEncoders(dataset.encoders, options.geometry,
                                                         dataset.info.ticks_per_revolution);
  inputs.imu = dataset.imu;
  inputs.groundtruth = dataset.groundtruth;
  // The oracle is the truth, mount included.
  inputs.T_base_lidar =
      method == algo::DeskewMethod::kOracle ? dataset.info.trueMount() : options.T_base_lidar;
  inputs.stamp_is_last_beam = options.stamp_is_last_beam;
  inputs.reference = options.reference;
  algo::DeskewParams params = options.params;
  params.max_sample_gap_s = sampleGapLimit(inputs, params.max_sample_gap_s);
  const algo::DeskewInputs none_inputs = noneInputs(inputs);
  algo::DeskewSequence sequence(method, std::move(inputs), params);
  DatasetDeskew out;
  PooledErrors pooled;
  for (std::size_t k = 0; k < dataset.scans.size(); ++k) {
    const ScanRecord& record = dataset.scans[k];
    const auto start = std::chrono::steady_clock::now();
    algo::DeskewResult result = sequence.next(record.scan);
    out.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const std::string note = !result.ok                ? result.reason
                             : result.warnings.empty() ? std::string()
                                                       : result.warnings.front();
    if (out.first_note.empty() && !note.empty())
      out.first_note = "scan " + std::to_string(k) + ": " + note;
    out.warnings += result.warnings.size();
    if (!result.ok && out.refused++ == 0) out.first_reason = result.reason;
    if (!result.ok) out.refusals.push_back({k, result.refusal, result.reason});
    const double stamp = record.scan.stamp_s;
    const bool counted =
        options.measure_errors && stamp >= options.measure_from_s && stamp <= options.measure_to_s;
    if (counted && !record.p_ref_true.empty()) {
      if (result.ok)
        measure(dataset, record, result, options.params.repacking, pooled);
      else
        measureAsMeasured(dataset, record, none_inputs, params, pooled);
    }
    out.scans.push_back(std::move(result));
    if (options.on_scan) options.on_scan(k + 1, dataset.scans.size());
  }
  out.fallback_error_m = fallbackErrors(pooled);
  if (pooled.total_m.empty()) return out;
  out.error_m = summarize(std::move(pooled.total_m));
  if (!pooled.repacked_m.empty()) {
    out.repacked_error_m = summarize(std::move(pooled.repacked_m));
    out.repacked_lost_beams = pooled.repacked_lost;
  }
  if (!pooled.split) return out;
  out.rotation_induced_m = summarize(std::move(pooled.rotation_m));
  out.translation_induced_m = summarize(std::move(pooled.translation_m));
  out.max_split_residual_m = pooled.max_residual_m;
  return out;
}

std::map<std::string, int> refusedByReason(const std::vector<ScanRefusal>& refusals) {
  std::map<std::string, int> out;
  for (const auto& r : refusals) ++out[std::string(algo::deskewRefusalName(r.reason))];
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
