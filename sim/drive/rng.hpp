#pragma once
// Seeded random streams: one per sensor, derived from the run seed and a fixed stream id, so
// adding a sensor never changes another sensor's noise. No wall clock, same bits everywhere.

#include <cmath>
#include <cstdint>
#include <numbers>

namespace slamprep::sim {

/// Fixed stream ids mixed into the run seed.
enum class RngStream : std::uint64_t {
  lidar = 0x6c696461ULL,         // "lida"
  encoders = 0x656e636fULL,      // "enco"
  imu = 0x696d7531ULL,           // "imu1"
  start_pose = 0x73747274ULL,    // "strt": the start_jitter draw
  encoder_slip = 0x736c6970ULL,  // "slip": random wheel slip (EncoderConfig::slip_sigma)
  people = 0x70656f70ULL,        // "peop": people about the robot (PeopleConfig)
  // One stream per fault (sim/drive/faults.hpp), so turning one on leaves the others' draws.
  fault_encoder_spikes = 0x66737069ULL,        // "fspi"
  fault_encoder_dropouts = 0x6664726fULL,      // "fdro"
  fault_jitter_encoders = 0x666a656eULL,       // "fjen"
  fault_jitter_imu = 0x666a696dULL,            // "fjim"
  fault_jitter_scans = 0x666a7363ULL,          // "fjsc"
  fault_dropped_scans = 0x66647363ULL,         // "fdsc"
  fault_dropped_beams = 0x66646265ULL,         // "fdbe"
  fault_imu_bias_drift = 0x66696d62ULL,        // "fimb"
  fault_stale_odometry = 0x6673746fULL,        // "fsto"
  fault_held_robot = 0x6668656cULL,            // "fhel"
  fault_read_jitter_encoders = 0x6672656aULL,  // "frej"
  fault_read_jitter_scans = 0x66727363ULL,     // "frsc"
  fault_sampling_encoders = 0x6673656eULL,     // "fsen"
};

/// SplitMix64 (Steele, Lea, Flood 2014): a tiny generator whose output is fully specified, so
/// the noise is the same with any standard library.
class SplitMix64 {
 public:
  explicit SplitMix64(std::uint64_t seed) : state_(seed) {}

  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  /// Uniform in [0, 1) with 53 random bits.
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
  /// Standard normal by the Box-Muller transform (both values used in turn).
  double gaussian() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    const double u1 = 1.0 - uniform();  // (0, 1]: log is finite
    const double u2 = uniform();
    const double r = std::sqrt(-2.0 * std::log(u1));
    spare_ = r * std::sin(2.0 * std::numbers::pi * u2);
    has_spare_ = true;
    return r * std::cos(2.0 * std::numbers::pi * u2);
  }

 private:
  std::uint64_t state_;
  double spare_ = 0.0;
  bool has_spare_ = false;
};

/// Seed of one sensor's stream: the run seed mixed with the stream id.
inline std::uint64_t streamSeed(std::uint64_t seed, RngStream stream) {
  SplitMix64 mix(seed ^ (static_cast<std::uint64_t>(stream) * 0xd1b54a32d192ed03ULL));
  return mix.next();
}

}  // namespace slamprep::sim
