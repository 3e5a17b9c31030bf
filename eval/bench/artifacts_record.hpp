#pragma once
// What the first trial keeps for the suite's plots ("artifacts" of a trial result): the true and
// dead-reckoned trajectories, the dead-reckoning error over time, and the most distorted scan
// raw, de-skewed and true, all in the world frame. Arrays only: nothing of it is summarised.

#include <array>
#include <cstddef>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "slamprep/core/dataset.hpp"
#include "slamprep/eval/pipeline/dataset_deskew.hpp"

namespace slamprep::eval {

/// Points (x, y) in the world frame [m], written as [[x, y], ...].
using WorldPoints = std::vector<std::array<double, 2>>;

/// Positions every 0.1 s ("trajectory").
struct TrajectoriesRecord {
  WorldPoints truth;                      ///< the ground truth ("true")
  WorldPoints nominal;                    ///< odometry with the nominal geometry
  std::optional<WorldPoints> calibrated;  ///< odometry with the best calibrated geometry
  std::string calibrated_method;          ///< which method calibrated it (with `calibrated`)

  bool operator==(const TrajectoriesRecord&) const = default;
};

/// Dead-reckoning error against the truth every 0.1 s, started on the true pose.
struct OdometryErrorSeries {
  std::vector<double> t;              ///< stamp [s]
  std::vector<double> translation_m;  ///< position error [m]
  std::vector<double> heading_deg;    ///< signed heading error [deg]

  bool operator==(const OdometryErrorSeries&) const = default;
};

/// "odometry_error": the nominal and (when calibrated) the calibrated geometry.
struct OdometryErrorRecord {
  OdometryErrorSeries nominal;                    ///< nominal geometry
  std::optional<OdometryErrorSeries> calibrated;  ///< best calibrated geometry

  bool operator==(const OdometryErrorRecord&) const = default;
};

/// The scan whose true lidar turned most while it was taken ("scan").
struct ArtifactScanRecord {
  std::size_t index = 0;                ///< its index in the dataset
  double stamp_s = 0.0;                 ///< its first beam's stamp
  std::array<double, 3> lidar{};        ///< the true lidar pose at the stamp (x, y, yaw)
  WorldPoints raw;                      ///< valid beams as measured (distorted)
  WorldPoints truth;                    ///< every beam's true undistorted point ("true")
  std::optional<WorldPoints> deskewed;  ///< corrected by `deskew_method`
  std::string deskew_method;            ///< with `deskewed`

  bool operator==(const ArtifactScanRecord&) const = default;
};

struct ArtifactsRecord {
  TrajectoriesRecord trajectory;           ///< "trajectory"
  OdometryErrorRecord odometry_error;      ///< "odometry_error"
  std::optional<ArtifactScanRecord> scan;  ///< nullopt without truth at the scan's stamp

  bool operator==(const ArtifactsRecord&) const = default;
};

/// The artifacts of a trial: `calibrated` (may be null) the best calibrated geometry,
/// `deskewed` (may be null) the de-skew the scan plot shows.
ArtifactsRecord artifactsRecord(const Dataset& dataset, const DiffDriveParams* calibrated,
                                const std::string& calibrated_method, const DatasetDeskew* deskewed,
                                const std::string& deskew_method);

void to_json(nlohmann::json& out, const TrajectoriesRecord& r);
void from_json(const nlohmann::json& in, TrajectoriesRecord& r);
void to_json(nlohmann::json& out, const OdometryErrorSeries& r);
void from_json(const nlohmann::json& in, OdometryErrorSeries& r);
void to_json(nlohmann::json& out, const OdometryErrorRecord& r);
void from_json(const nlohmann::json& in, OdometryErrorRecord& r);
void to_json(nlohmann::json& out, const ArtifactScanRecord& r);
void from_json(const nlohmann::json& in, ArtifactScanRecord& r);
void to_json(nlohmann::json& out, const ArtifactsRecord& r);
void from_json(const nlohmann::json& in, ArtifactsRecord& r);

}  // namespace slamprep::eval
