#pragma once
// A rotating 2D lidar whose beams are taken one after another, each from its own pose.

#include <cstdint>
#include <numbers>
#include <optional>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include "slamprep/core/laser_scan.hpp"
#include "slamprep/core/se2.hpp"
#include "slamprep/sim/physics/scene.hpp"
#include "slamprep/sim/physics/surface_texture.hpp"

namespace slamprep::sim {

struct LidarConfig {
  double rate_hz = 10.0;  ///< scans per second
  /// How long the head takes for one revolution: 0 is 1 / rate_hz. Shorter where the head turns
  /// faster than scans are published (a Neato's 5 Hz head published at 4.4 Hz, an RPLIDAR's
  /// 0.122 s revolutions 0.130 s apart): each scan's beams span this, then the head's next
  /// revolutions until the next scan are not published.
  double sweep_s = 0.0;
  /// With sweep_s shorter than 1 / rate_hz: the head turns on at its own rate, unsynchronised
  /// with the publishing, and each scan (stamped on the publishing grid) holds the revolution
  /// that began nearest its stamp, which starts up to half a revolution before or after it: a
  /// sawtooth over the scans (a Neato's 5 Hz head read by its driver at 4.65 Hz). Zero on
  /// average: a constant age is the clock offset fault's. False: every scan starts at its stamp.
  bool free_running = false;
  int beams_per_revolution = 720;         ///< angular resolution: 2 pi / this
  double fov_rad = 2 * std::numbers::pi;  ///< scan covers this much of the revolution
  double range_min_m = 0.05;              ///< shorter returns are reported as no return
  double range_max_m = 30.0;              ///< longer returns are reported as no return
  double range_noise_m = 0.01;            ///< Gaussian sigma
  /// Correlation of consecutive beams' range noise within a scan (AR(1) along the beams, sigma
  /// kept; 0: white).
  double range_noise_correlation = 0.0;
  /// Sigma of a range error fixed in the world (SurfaceTexture: the same wherever a spot is seen
  /// again), added to the per-scan noise; 0: none.
  double range_noise_fixed_m = 0.0;
  double range_noise_fixed_length_m = 0.02;  ///< its correlation length along a surface
  /// A range error fixed in the lidar's own frame: metres added to beam i's range, comma
  /// separated in beam order ("": none; beams beyond the list: 0). A head whose range
  /// calibration varies with its angle reads some beams long wherever it is.
  std::string range_bias_by_beam_m;
  /// A range error that depends on the range: metres added to a return at 0, 1, 2, ... m of true
  /// range, comma separated, interpolated linearly and held beyond the last ("": none). A
  /// triangulation head's error grows with range, so a wall seen from two ranges bends.
  std::string range_bias_by_range_m;
  bool clockwise = false;                                 ///< negative angle_increment
  SE2 T_base_lidar{0.1, 0.02, std::numbers::pi / 180.0};  ///< mount on the chassis
  double height_m = 0.25;                                 ///< above the floor
};

/// Reads LidarConfig::range_bias_by_beam_m: comma-separated finite numbers within [-1, 1] m
/// ("" gives none); nullopt (and *error set) otherwise. The same for range_bias_by_range_m.
std::optional<std::vector<double>> parseRangeBias(std::string_view text, std::string* error);

/// range_bias_by_range_m's curve at `range_m`: knots at whole metres, linear between, the end
/// knots held beyond (0 for an empty curve).
double rangeBiasAt(const std::vector<double>& bias_by_metre_m, double range_m);

/// A rotating 2D lidar: beam i of a scan is taken at its own time from its own pose.
class Lidar {
 public:
  Lidar(const LidarConfig& config, std::uint64_t seed);
  const LidarConfig& config() const { return config_; }
  std::size_t beamsPerScan() const { return beams_per_scan_; }  // round(bpr * fov / 2pi)
  /// Scan header with stamp = first beam, ROS convention (angle_min, angle_increment,
  /// time_increment = sweep / beams_per_revolution, sweep = sweep_s or 1 / rate, scan_time =
  /// 1 / rate, range limits), ranges_m sized beamsPerScan() and filled with +inf.
  LaserScan header(double stamp_s) const;
  struct Beam {
    double range_m;       ///< measured: true + noise; +inf for no return
    double true_range_m;  ///< geometric distance; +inf when nothing within range_max
  };
  /// Where scan `stamp_s`'s revolution starts against its stamp: 0, or with free_running the
  /// revolution boundary of a head turning every sweep_s since 0 nearest the stamp.
  double revolutionOffset(double stamp_s) const;
  /// Measures beam i from the lidar pose at that beam's time. Draws noise from the lidar's own
  /// seeded generator, so call it in beam order.
  Beam measure(const Scene& scene, const SE2& T_world_lidar, std::size_t i);
  /// The same with the beam's world-frame origin and unit direction given (callers that keep
  /// the lidar's rotation as cosine and sine avoid the trigonometry), and what moves in the
  /// world: `moving_m`, the range to something not in the scene (people), where nearer.
  Beam measure(const Scene& scene, const Eigen::Vector2d& origin_world_m,
               const Eigen::Vector2d& dir_world, std::size_t i,
               std::optional<double> moving_m = std::nullopt);
  /// Angle of beam i in the lidar frame (same as header().beamAngle(i)).
  double beamAngle(std::size_t i) const { return angle_min_rad_ + i * angle_increment_rad_; }

 private:
  double gaussian();

  LidarConfig config_;
  std::size_t beams_per_scan_ = 0;
  double angle_min_rad_ = 0.0;
  double angle_increment_rad_ = 0.0;
  std::mt19937_64 rng_;
  std::optional<SurfaceTexture> texture_;  ///< with range_noise_fixed_m
  std::vector<double> bias_by_beam_m_;     ///< range_bias_by_beam_m, parsed
  std::vector<double> bias_by_range_m_;    ///< range_bias_by_range_m, parsed
  double spare_gaussian_ = 0.0;
  bool has_spare_ = false;
  double last_noise_m_ = 0.0;  ///< the previous beam's, for range_noise_correlation
};

}  // namespace slamprep::sim
