#pragma once
// Faults real robots have and a clean simulation lacks: encoder spikes and dropouts, stamp
// jitter, a lidar-odometry clock offset, dropped scans and beams, IMU bias drift, slippery floor,
// glass, stale odometry that catches up, and a held robot whose wheels turn. Each is off by
// default, switched on by name (`--set faults.enable=...`), has its own seeded stream, and every
// injected event is recorded in dataset.json (docs/faults.md).

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "slamprep/core/enum_names.hpp"
#include "slamprep/sim/drive/rng.hpp"

namespace slamprep::sim {

enum class Fault : std::uint8_t {
  encoder_spikes,    ///< one encoder sample of one wheel off by +-ticks, the next ones right
  encoder_dropouts,  ///< no encoder samples for a while
  stamp_jitter,      ///< Gaussian error on every sensor stamp
  clock_offset,      ///< constant lidar clock offset against the odometry's
  dropped_scans,     ///< whole scans lost
  dropped_beams,     ///< single beams without a return
  imu_bias_drift,    ///< gyro bias as a random walk
  floor_patches,     ///< the world's low-friction floor patches make the wheels slip
  glass,             ///< the world's `returns: false` objects give no lidar return
  stale_odometry,    ///< the encoders repeat their last value for a while, then jump to the truth
  held_robot,        ///< the body is held still while the wheels turn as commanded
  read_jitter,       ///< encoders read and scans taken off their stamps, which stay on their grid
};

/// Every fault with its name, in the order the names are written.
inline constexpr auto kFaultNames = std::to_array<EnumName<Fault>>({
    {Fault::encoder_spikes, "encoder_spikes"},
    {Fault::encoder_dropouts, "encoder_dropouts"},
    {Fault::stamp_jitter, "stamp_jitter"},
    {Fault::clock_offset, "clock_offset"},
    {Fault::dropped_scans, "dropped_scans"},
    {Fault::dropped_beams, "dropped_beams"},
    {Fault::imu_bias_drift, "imu_bias_drift"},
    {Fault::floor_patches, "floor_patches"},
    {Fault::glass, "glass"},
    {Fault::stale_odometry, "stale_odometry"},
    {Fault::held_robot, "held_robot"},
    {Fault::read_jitter, "read_jitter"},
});

std::string_view faultName(Fault fault);

/// Which faults are on.
class FaultSet {
 public:
  bool has(Fault f) const { return (bits_ >> static_cast<unsigned>(f)) & 1U; }
  void add(Fault f) { bits_ |= 1U << static_cast<unsigned>(f); }
  bool any() const { return bits_ != 0; }
  bool operator==(const FaultSet&) const = default;

 private:
  std::uint32_t bits_ = 0;
};

/// "none", or the names of the faults on joined by commas in kFaultNames order.
std::string toString(const FaultSet& faults);
/// Reads "none", "all" or comma-separated names; nullopt (and *error set) for an unknown name.
std::optional<FaultSet> parseFaultSet(std::string_view text, std::string* error);

/// Reads comma-separated factors >= 0 ("" gives none); nullopt (and *error set) otherwise.
std::optional<std::vector<double>> parseFactors(std::string_view text, std::string* error);

/// Strength of every fault: used only when the fault is in `enable`. The defaults are ordinary
/// for a real indoor robot (docs/faults.md says where each comes from).
struct FaultsConfig {
  FaultSet enable;                          ///< faults.enable: all off by default
  double encoder_spike_rate_hz = 0.01;      ///< spikes per second (1 per 100 s)
  int encoder_spike_ticks = 500;            ///< size of a spike, sign random
  double encoder_dropout_rate_hz = 0.01;    ///< dropouts per second
  double encoder_dropout_duration_s = 0.2;  ///< no samples for this long
  double stamp_jitter_sigma_s = 0.001;      ///< per stamp, cut at 0.45 sample periods
  /// Per stream, for a twin of a recording whose streams jitter differently; < 0: sigma_s.
  double stamp_jitter_encoders_sigma_s = -1.0;
  double stamp_jitter_imu_sigma_s = -1.0;
  double stamp_jitter_scans_sigma_s = -1.0;
  /// Encoders sampled at irregular times and stamped right (a robot that stamps its own
  /// odometry): sample k is taken and stamped at its grid time + s_k, s_k ~ N(0, this^2) cut at
  /// 0.45 periods, before any stamp error above; 0: sampled on the grid.
  double stamp_jitter_encoders_sampling_sigma_s = 0.0;
  double jitterSigma(double stream_sigma_s) const {
    return stream_sigma_s < 0.0 ? stamp_jitter_sigma_s : stream_sigma_s;
  }
  double clock_offset_s = 0.005;            ///< lidar stamps = true time + this
  double dropped_scan_probability = 0.01;   ///< per scan
  double dropped_beam_probability = 0.005;  ///< per beam
  /// The no-return pattern of a real lidar (a sector its housing blocks, fewer returns far away):
  /// comma-separated factors on a beam's chance of a return, (1 - probability) x angle factor x
  /// range factor, capped at 1. by_angle: equal bins of the beam's angle in the lidar frame over
  /// [-180, 180) deg; by_range: bins of range_bin_m from 0 (the last one beyond). "" = 1.
  std::string dropped_beam_by_angle;
  std::string dropped_beam_by_range;
  double dropped_beam_range_bin_m = 0.5;
  double imu_gyro_bias_walk_radps = 1e-4;  ///< gyro bias random walk, rad/s per sqrt(s)
  double stale_odometry_rate_hz = 0.01;    ///< holds per second
  double stale_odometry_min_hold_s = 0.3;  ///< each hold lasts uniform [min, max]
  double stale_odometry_max_hold_s = 1.0;
  double held_robot_rate_hz = 0.01;        ///< holds of the body per second
  double held_robot_min_duration_s = 1.0;  ///< each lasts uniform [min, max]
  double held_robot_max_duration_s = 3.0;
  /// When the encoders are read against their stamps: N(0, sigma^2) ...
  double read_jitter_encoders_sigma_s = 0.02;
  /// ... correlated from sample to sample over this time (AR(1), exp(-dt / this), sigma kept;
  /// 0: white): a reading late for a while, as a busy driver's is, not independently each time.
  double read_jitter_encoders_correlation_s = 0.0;
  /// When a scan's first beam is taken against its stamp: N(0, sigma^2), cut at 0.45 periods.
  double read_jitter_scans_sigma_s = 0.0;
};

/// One time error of a stream at `rate_hz`: N(0, sigma^2) cut to +-0.45 periods, so samples
/// keep their order (stamp_jitter's stamps, read_jitter's scans).
double periodJitter(SplitMix64& rng, double sigma_s, double rate_hz);

/// When scan after scan is taken against its stamp (Fault::read_jitter): one draw per scan of
/// the clean log, in order, from the fault's own stream; 0 while the fault is off. The first
/// scan is not taken before t = 0, where the run starts.
class ScanReadJitter {
 public:
  ScanReadJitter(const FaultsConfig& f, std::uint64_t seed, double lidar_hz);
  double next();

 private:
  double sigma_s_, lidar_hz_;
  SplitMix64 rng_;
  bool first_ = true;
};

}  // namespace slamprep::sim
