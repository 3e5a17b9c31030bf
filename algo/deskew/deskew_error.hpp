#pragma once
// De-skew error against ground truth: per-beam distance between a corrected point and the true
// undistorted point of the same beam (both in the lidar frame at the same reference time).

#include <Eigen/Core>
#include <cstddef>
#include <optional>
#include <vector>

namespace slamprep::algo {

struct DeskewError {
  double mean_m = 0.0;
  double rms_m = 0.0;
  double p95_m = 0.0;  ///< 95th percentile (nearest rank)
  double max_m = 0.0;
  std::size_t beams = 0;  ///< beams with both a corrected and a true point
};

/// Collects per-beam distances over any number of scans.
class DeskewErrorAccumulator {
 public:
  /// Adds every beam that has both points; sizes must match (the same beam grid).
  void add(const std::vector<std::optional<Eigen::Vector2d>>& p_ref,
           const std::vector<std::optional<Eigen::Vector2d>>& p_true);
  DeskewError summary() const;

 private:
  std::vector<double> distances_m_;
};

/// The error of one scan.
DeskewError deskewError(const std::vector<std::optional<Eigen::Vector2d>>& p_ref,
                        const std::vector<std::optional<Eigen::Vector2d>>& p_true);

}  // namespace slamprep::algo
