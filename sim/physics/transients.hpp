#pragma once
// What a world holds only for a moment (docs/worlds.md "Transients"): discs the lidar sees between
// two times and the physics never meets. A twin replays its recording's transient returns so:
// people walking by, a door, a chair moved, clutter seen once.

#include <Eigen/Core>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace slamprep::sim {

struct Transient {
  double from_s = 0.0, to_s = 0.0;     ///< simulated time it is there
  Eigen::Vector2d center_m{0.0, 0.0};  ///< world frame
  double radius_m = 0.05;
};

/// A transients file: CSV with the header `from_s,to_s,x_m,y_m,radius_m` and one transient per
/// line (from_s <= to_s, radius in (0, 10] m). Throws InputError("file:line", ...) on bad input.
std::vector<Transient> loadTransients(const std::filesystem::path& file);

/// The same format, written.
std::string transientsCsv(const std::vector<Transient>& transients);

/// Casts rays against the transients present at a time; fastest when the times asked do not
/// decrease (a scan's beams), exact when they step back (a scan read early).
class TransientCaster {
 public:
  explicit TransientCaster(std::vector<Transient> transients);
  /// Range along the ray (origin, unit dir) to the nearest transient present at t_s; nullopt
  /// for none within max_range_m or a ray that starts inside one.
  std::optional<double> castRay(const Eigen::Vector2d& origin, const Eigen::Vector2d& dir,
                                double t_s, double max_range_m);

 private:
  std::vector<Transient> by_start_;  ///< sorted by from_s
  double longest_s_ = 0.0;           ///< the longest to_s - from_s
  double last_t_s_ = 0.0;
  std::size_t next_ = 0;  ///< the first not yet present
  std::vector<std::size_t> present_;
};

/// Range to the disc (centre c, radius r) along the ray p + s d (|d| = 1), s > 0: the near root of
/// |p + s d - c|^2 = r^2; nullopt where the ray misses it or starts inside it.
std::optional<double> rayDisc(const Eigen::Vector2d& p, const Eigen::Vector2d& d,
                              const Eigen::Vector2d& c, double r);

}  // namespace slamprep::sim
