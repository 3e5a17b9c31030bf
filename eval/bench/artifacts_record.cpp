#include "slamprep/eval/bench/artifacts_record.hpp"

#include <cmath>
#include <numbers>

#include "slamprep/core/odometry.hpp"
#include "slamprep/eval/bench/record_fields.hpp"
#include "slamprep/eval/metrics/odometry_drift.hpp"

namespace slamprep::eval {
namespace {

using nlohmann::json;

constexpr double kStepS = 0.1;  // plots need no more

// Positions of a trajectory every `step_s`.
WorldPoints decimated(const PoseSeries& poses, double step_s) {
  WorldPoints points;
  double next = -1e300;
  for (const auto& s : poses.samples())
    if (s.stamp_s >= next) {
      points.push_back({s.value.translation().x(), s.value.translation().y()});
      next = s.stamp_s + step_s;
    }
  return points;
}

// Dead-reckoning error against the truth every `step_s`, with both started on the true start
// pose (evo's APE, aligned at the first pose).
OdometryErrorSeries odometryError(const PoseSeries& truth, const PoseSeries& odometry_world,
                                  double step_s) {
  OdometryErrorSeries out;
  double next = -1e300;
  for (const auto& s : odometry_world.samples()) {
    if (s.stamp_s < next) continue;
    const auto T_true = truth.at(s.stamp_s);
    if (!T_true) continue;
    const SE2 e = T_true->inverse() * s.value;
    out.t.push_back(s.stamp_s);
    out.translation_m.push_back((s.value.translation() - T_true->translation()).norm());
    out.heading_deg.push_back(e.yaw * 180.0 / std::numbers::pi);
    next = s.stamp_s + step_s;
  }
  return out;
}

// The scan whose true lidar turned most while it was taken: where distortion shows best.
std::size_t mostDistortedScan(const Dataset& dataset) {
  std::size_t best = 0;
  double best_turn = -1.0;
  for (std::size_t k = 0; k < dataset.scans.size(); ++k) {
    const auto& scan = dataset.scans[k].scan;
    const auto a = dataset.groundtruth.at(scan.stamp_s), b = dataset.groundtruth.at(scan.endTime());
    if (a && b && std::abs(between(*a, *b).yaw) > best_turn) {
      best_turn = std::abs(between(*a, *b).yaw);
      best = k;
    }
  }
  return best;
}

// The most distorted scan raw, true and (when given) de-skewed, in the world frame.
std::optional<ArtifactScanRecord> shownScan(const Dataset& dataset, const DatasetDeskew* deskewed,
                                            const std::string& deskew_method) {
  const std::size_t k = mostDistortedScan(dataset);
  const ScanRecord& record = dataset.scans[k];
  const auto T_world_base = dataset.groundtruth.at(record.scan.stamp_s);
  if (!T_world_base) return std::nullopt;
  const SE2 T_world_lidar = *T_world_base * dataset.info.trueMount();
  const auto toWorld = [&](const std::vector<std::optional<Eigen::Vector2d>>& p_lidar) {
    WorldPoints points;
    for (const auto& p : p_lidar)
      if (p) {
        const Eigen::Vector2d p_world = T_world_lidar * *p;
        points.push_back({p_world.x(), p_world.y()});
      }
    return points;
  };
  std::vector<std::optional<Eigen::Vector2d>> raw;
  for (std::size_t i = 0; i < record.scan.size(); ++i)
    if (record.scan.valid(i)) raw.push_back(record.scan.point(i));
  ArtifactScanRecord scan{.index = k,
                          .stamp_s = record.scan.stamp_s,
                          .lidar = {T_world_lidar.x, T_world_lidar.y, T_world_lidar.yaw},
                          .raw = toWorld(raw),
                          .truth = toWorld(record.p_ref_true),
                          .deskewed = std::nullopt,
                          .deskew_method = {}};
  if (deskewed && deskewed->scans[k].ok) {
    scan.deskewed = toWorld(deskewed->scans[k].p_ref);
    scan.deskew_method = deskew_method;
  }
  return scan;
}

}  // namespace

ArtifactsRecord artifactsRecord(const Dataset& dataset, const DiffDriveParams* calibrated,
                                const std::string& calibrated_method, const DatasetDeskew* deskewed,
                                const std::string& deskew_method) {
  ArtifactsRecord out;
  out.trajectory.truth = decimated(dataset.groundtruth, kStepS);
  const auto odometryInWorld = [&](const DiffDriveParams& geometry) {
    const PoseSeries odom =
        integrateEncoders(dataset.encoders, geometry, dataset.info.ticks_per_revolution);
    return inWorld(odom, anchorOnTruth(odom, dataset.groundtruth).value_or(SE2()));
  };
  const PoseSeries nominal = odometryInWorld(dataset.info.nominal_geometry);
  out.trajectory.nominal = decimated(nominal, kStepS);
  out.odometry_error.nominal = odometryError(dataset.groundtruth, nominal, kStepS);
  if (calibrated) {
    const PoseSeries world = odometryInWorld(*calibrated);
    out.trajectory.calibrated = decimated(world, kStepS);
    out.odometry_error.calibrated = odometryError(dataset.groundtruth, world, kStepS);
    out.trajectory.calibrated_method = calibrated_method;
  }
  out.scan = shownScan(dataset, deskewed, deskew_method);
  return out;
}

void to_json(json& out, const TrajectoriesRecord& r) {
  out = {{"true", r.truth}, {"nominal", r.nominal}};
  if (r.calibrated) {
    out["calibrated"] = *r.calibrated;
    out["calibrated_method"] = r.calibrated_method;
  }
}

void from_json(const json& in, TrajectoriesRecord& r) {
  r.truth = readField<WorldPoints>(in, "true");
  r.nominal = readField<WorldPoints>(in, "nominal");
  r.calibrated = readOptional<WorldPoints>(in, "calibrated");
  r.calibrated_method = in.value("calibrated_method", std::string());
}

void to_json(json& out, const OdometryErrorSeries& r) {
  out = {{"t", r.t}, {"translation_m", r.translation_m}, {"heading_deg", r.heading_deg}};
}

void from_json(const json& in, OdometryErrorSeries& r) {
  r.t = readField<std::vector<double>>(in, "t");
  r.translation_m = readField<std::vector<double>>(in, "translation_m");
  r.heading_deg = readField<std::vector<double>>(in, "heading_deg");
}

void to_json(json& out, const OdometryErrorRecord& r) {
  out = {{"nominal", r.nominal}};
  writeOptional(out, "calibrated", r.calibrated);
}

void from_json(const json& in, OdometryErrorRecord& r) {
  r.nominal = readField<OdometryErrorSeries>(in, "nominal");
  r.calibrated = readOptional<OdometryErrorSeries>(in, "calibrated");
}

void to_json(json& out, const ArtifactScanRecord& r) {
  out = {{"index", r.index},
         {"stamp_s", r.stamp_s},
         {"lidar", r.lidar},
         {"raw", r.raw},
         {"true", r.truth}};
  if (r.deskewed) {
    out["deskewed"] = *r.deskewed;
    out["deskew_method"] = r.deskew_method;
  }
}

void from_json(const json& in, ArtifactScanRecord& r) {
  r.index = readField<std::size_t>(in, "index");
  r.stamp_s = readField<double>(in, "stamp_s");
  r.lidar = readField<std::array<double, 3>>(in, "lidar");
  r.raw = readField<WorldPoints>(in, "raw");
  r.truth = readField<WorldPoints>(in, "true");
  r.deskewed = readOptional<WorldPoints>(in, "deskewed");
  r.deskew_method = in.value("deskew_method", std::string());
}

void to_json(json& out, const ArtifactsRecord& r) {
  out = {{"trajectory", r.trajectory}, {"odometry_error", r.odometry_error}};
  writeOptional(out, "scan", r.scan);
}

void from_json(const json& in, ArtifactsRecord& r) {
  r.trajectory = readField<TrajectoriesRecord>(in, "trajectory");
  r.odometry_error = readField<OdometryErrorRecord>(in, "odometry_error");
  r.scan = readOptional<ArtifactScanRecord>(in, "scan");
}

}  // namespace slamprep::eval
