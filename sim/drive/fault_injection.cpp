#include "slamprep/sim/drive/fault_injection.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "slamprep/sim/drive/fault_windows.hpp"
#include "slamprep/sim/drive/rng.hpp"

namespace slamprep::sim {
namespace {

using nlohmann::json;

SplitMix64 stream(std::uint64_t seed, RngStream id) {
  return SplitMix64(streamSeed(seed, id));
}

/// One stamp error per sample (periodJitter).
std::vector<double> jitter(SplitMix64& rng, std::size_t n, double sigma_s, double rate_hz) {
  std::vector<double> out(n);
  for (double& e : out) e = periodJitter(rng, sigma_s, rate_hz);
  return out;
}

json jitterSummary(const std::vector<double>& errors) {
  double sum2 = 0.0, max_abs = 0.0;
  for (double e : errors) {
    sum2 += e * e;
    max_abs = std::max(max_abs, std::abs(e));
  }
  const double rms = errors.empty() ? 0.0 : std::sqrt(sum2 / errors.size());
  return {{"count", errors.size()}, {"rms_s", rms}, {"max_abs_s", max_abs}};
}

// ---- Encoders --------------------------------------------------------------------------------

/// Stale odometry: the samples stamped inside a window repeat the last value before it (the
/// stamps go on); the first sample after it reads the true count again, one jump of everything
/// the wheels turned meanwhile. Sample 0 has no earlier value and is never held.
json holdEncoders(const FaultsConfig& f, std::uint64_t seed, double duration_s, EncoderLog& log) {
  SplitMix64 rng = stream(seed, RngStream::fault_stale_odometry);
  json events = json::array();
  const auto at = [&log](double t) {
    return std::lower_bound(log.begin(), log.end(), t,
                            [](const EncoderSample& s, double v) { return s.stamp_s < v; });
  };
  for (const TimeWindow& w :
       poissonWindows(rng, f.stale_odometry_rate_hz, f.stale_odometry_min_hold_s,
                      f.stale_odometry_max_hold_s, duration_s)) {
    auto first = at(w.from_s);
    if (first == log.begin() && first != log.end()) ++first;
    const auto end = std::max(first, at(w.to_s));
    json event = {{"t_from_s", w.from_s},
                  {"t_to_s", w.to_s},
                  {"sample", first - log.begin()},
                  {"samples", end - first}};
    if (first != end) {
      const EncoderSample held = *(first - 1);
      for (auto it = first; it != end; ++it) {
        it->ticks_left = held.ticks_left;
        it->ticks_right = held.ticks_right;
      }
      if (end != log.end())  // the catch-up: the true count again, in one step
        event["jump_ticks"] = {end->ticks_left - held.ticks_left,
                               end->ticks_right - held.ticks_right};
    }
    events.push_back(event);
  }
  return {{"rate_hz", f.stale_odometry_rate_hz},
          {"min_hold_s", f.stale_odometry_min_hold_s},
          {"max_hold_s", f.stale_odometry_max_hold_s},
          {"events", events}};
}

/// A spike: the first sample at or after the event time reads `ticks` too many on one wheel.
json injectSpikes(const FaultsConfig& f, std::uint64_t seed, double duration_s, EncoderLog& log) {
  SplitMix64 rng = stream(seed, RngStream::fault_encoder_spikes);
  json events = json::array();
  for (const double t : poissonTimes(rng, f.encoder_spike_rate_hz, duration_s)) {
    const bool left = rng.uniform() < 0.5;
    const std::int64_t ticks = (rng.uniform() < 0.5 ? -1 : 1) * std::int64_t{f.encoder_spike_ticks};
    const auto it = std::lower_bound(
        log.begin(), log.end(), t, [](const EncoderSample& s, double v) { return s.stamp_s < v; });
    if (it == log.end()) continue;
    (left ? it->ticks_left : it->ticks_right) += ticks;
    events.push_back({{"t_s", it->stamp_s},
                      {"sample", it - log.begin()},
                      {"wheel", left ? "left" : "right"},
                      {"ticks", ticks}});
  }
  return {
      {"rate_hz", f.encoder_spike_rate_hz}, {"ticks", f.encoder_spike_ticks}, {"events", events}};
}

/// Dropout windows [t, t + duration) in true time; returns the record and fills `windows`.
json dropoutWindows(const FaultsConfig& f, std::uint64_t seed, double duration_s,
                    std::vector<std::pair<double, double>>& windows) {
  SplitMix64 rng = stream(seed, RngStream::fault_encoder_dropouts);
  json events = json::array();
  for (const double t : poissonTimes(rng, f.encoder_dropout_rate_hz, duration_s)) {
    windows.emplace_back(t, t + f.encoder_dropout_duration_s);
    events.push_back({{"t_from_s", t}, {"t_to_s", t + f.encoder_dropout_duration_s}});
  }
  return {{"rate_hz", f.encoder_dropout_rate_hz},
          {"duration_s", f.encoder_dropout_duration_s},
          {"events", events}};
}

bool inWindow(const std::vector<std::pair<double, double>>& windows, double t) {
  return std::any_of(windows.begin(), windows.end(),
                     [t](const auto& w) { return t >= w.first && t < w.second; });
}

// ---- Scans -----------------------------------------------------------------------------------

/// A beam's chance of a return: (1 - probability), times the factor of its angle's bin and of
/// its range's bin (FaultsConfig), capped at 1.
class BeamKeep {
 public:
  explicit BeamKeep(const FaultsConfig& f)
      : keep_(1.0 - f.dropped_beam_probability),
        by_angle_(parseFactors(f.dropped_beam_by_angle, nullptr).value_or(std::vector<double>{})),
        by_range_(parseFactors(f.dropped_beam_by_range, nullptr).value_or(std::vector<double>{})),
        range_bin_m_(f.dropped_beam_range_bin_m) {}

  bool shaped() const { return !by_angle_.empty() || !by_range_.empty(); }

  double returnProbability(double angle_rad, double range_m) const {
    double keep = keep_;
    if (!by_angle_.empty()) {
      const double turn = (std::remainder(angle_rad, 2 * std::numbers::pi) + std::numbers::pi) /
                          (2 * std::numbers::pi);  // [0, 1] from -180 deg
      keep *= by_angle_[std::min(by_angle_.size() - 1,
                                 static_cast<std::size_t>(turn * double(by_angle_.size())))];
    }
    if (!by_range_.empty() && std::isfinite(range_m))
      keep *= by_range_[std::min(by_range_.size() - 1,
                                 static_cast<std::size_t>(std::max(0.0, range_m) / range_bin_m_))];
    return std::min(1.0, keep);
  }

 private:
  double keep_;
  std::vector<double> by_angle_, by_range_;
  double range_bin_m_;
};

/// Dropped beams by the scan's index in the clean log; the beam reads no return. One draw per
/// beam, shaped or not, so the same seed drops the same beams of an unshaped run.
json dropBeams(const FaultsConfig& f, std::uint64_t seed, std::vector<ScanRecord>& scans) {
  SplitMix64 rng = stream(seed, RngStream::fault_dropped_beams);
  const BeamKeep keep(f);
  json events = json::array();
  std::size_t count = 0;
  for (std::size_t k = 0; k < scans.size(); ++k) {
    ScanRecord& r = scans[k];
    json beams = json::array();
    for (std::size_t i = 0; i < r.scan.size(); ++i) {
      const double u = rng.uniform();
      // A replayed return was one the recording had: its dropouts are already the recording's.
      if (std::find(r.replayed_beams.begin(), r.replayed_beams.end(), i) != r.replayed_beams.end())
        continue;
      const bool drop = keep.shaped()
                            ? !(u < keep.returnProbability(r.scan.beamAngle(i), r.scan.ranges_m[i]))
                            : u < f.dropped_beam_probability;
      if (!drop) continue;
      r.scan.ranges_m[i] = std::numeric_limits<double>::infinity();
      if (i < r.p_ref_true.size()) r.p_ref_true[i].reset();
      beams.push_back(i);
    }
    count += beams.size();
    if (!beams.empty()) events.push_back({{"scan", k}, {"beams", beams}});
  }
  json record = {{"probability", f.dropped_beam_probability}, {"count", count}, {"events", events}};
  if (keep.shaped()) {
    record["by_angle"] = f.dropped_beam_by_angle;
    record["by_range"] = f.dropped_beam_by_range;
    record["range_bin_m"] = f.dropped_beam_range_bin_m;
  }
  return record;
}

std::vector<bool> droppedScans(const FaultsConfig& f, std::uint64_t seed, double lidar_hz,
                               const std::vector<ScanRecord>& scans, json& record) {
  SplitMix64 rng = stream(seed, RngStream::fault_dropped_scans);
  std::vector<bool> dropped(scans.size());
  json events = json::array();
  for (std::size_t k = 0; k < scans.size(); ++k) {
    dropped[k] = rng.uniform() < f.dropped_scan_probability;
    if (dropped[k]) events.push_back({{"scan", k}, {"t_s", static_cast<double>(k) / lidar_hz}});
  }
  record = {{"probability", f.dropped_scan_probability}, {"events", events}};
  return dropped;
}

/// Gyro bias random walk: b_k = b_{k-1} + q sqrt(dt) n_k, added to every sample; the record
/// keeps the bias once per second.
json driftImu(const FaultsConfig& f, std::uint64_t seed, ImuLog& imu) {
  SplitMix64 rng = stream(seed, RngStream::fault_imu_bias_drift);
  json series = json::array();
  double bias = 0.0, t_prev = imu.empty() ? 0.0 : imu.front().stamp_s, next_record = 0.0;
  for (ImuSample& s : imu) {
    bias +=
        f.imu_gyro_bias_walk_radps * std::sqrt(std::max(0.0, s.stamp_s - t_prev)) * rng.gaussian();
    t_prev = s.stamp_s;
    s.gyro_z_radps += bias;
    if (s.stamp_s >= next_record) {
      series.push_back({s.stamp_s, bias});
      next_record += 1.0;
    }
  }
  return {{"gyro_walk_radps_per_sqrt_s", f.imu_gyro_bias_walk_radps},
          {"final_bias_radps", bias},
          {"bias_radps", series}};
}

/// The clean log's ticks at t, linear between the samples around it (the ends held).
std::pair<double, double> ticksAt(const EncoderLog& clean, double t) {
  const auto upper =
      std::upper_bound(clean.begin(), clean.end(), t,
                       [](double s, const EncoderSample& e) { return s < e.stamp_s; });
  if (upper == clean.begin())
    return {double(clean.front().ticks_left), double(clean.front().ticks_right)};
  if (upper == clean.end())
    return {double(clean.back().ticks_left), double(clean.back().ticks_right)};
  const EncoderSample& a = *(upper - 1);
  const EncoderSample& b = *upper;
  const double f = (t - a.stamp_s) / (b.stamp_s - a.stamp_s);
  return {double(a.ticks_left) + f * double(b.ticks_left - a.ticks_left),
          double(a.ticks_right) + f * double(b.ticks_right - a.ticks_right)};
}

/// Every encoder sample read e_k off its stamp, which stays: its ticks are the clean log's at
/// stamp + e_k. A driver that stamps on arrival, or a log that pairs each scan with the last
/// odometry it had, looks like this: regular stamps, readings of varying age.
json readOffStamps(const FaultsConfig& f, std::uint64_t seed, EncoderLog& encoders) {
  SplitMix64 rng = stream(seed, RngStream::fault_read_jitter_encoders);
  std::vector<double> e(encoders.size());  // not cut: a reading may be older than the one before
  for (double& x : e) x = f.read_jitter_encoders_sigma_s * rng.gaussian();
  if (const double tau = f.read_jitter_encoders_correlation_s; tau > 0.0)
    for (std::size_t k = 1; k < e.size(); ++k) {  // AR(1) of the same draws, sigma kept
      const double rho = std::exp(-(encoders[k].stamp_s - encoders[k - 1].stamp_s) / tau);
      e[k] = rho * e[k - 1] + std::sqrt(1.0 - rho * rho) * e[k];
    }
  const EncoderLog clean = encoders;
  for (std::size_t k = 0; k < encoders.size(); ++k) {
    const auto [left, right] = ticksAt(clean, clean[k].stamp_s + e[k]);
    encoders[k].ticks_left = std::llround(left);
    encoders[k].ticks_right = std::llround(right);
  }
  return jitterSummary(e);
}

/// Every encoder sample taken s_k off its grid time and stamped then: stamp and ticks move
/// together (the clean log's ticks at grid + s_k), so the ticks follow the irregular stamps.
json sampleOffGrid(const FaultsConfig& f, std::uint64_t seed, double rate_hz,
                   EncoderLog& encoders) {
  SplitMix64 rng = stream(seed, RngStream::fault_sampling_encoders);
  const auto s = jitter(rng, encoders.size(), f.stamp_jitter_encoders_sampling_sigma_s, rate_hz);
  const EncoderLog clean = encoders;
  for (std::size_t k = 0; k < encoders.size(); ++k) {
    const double t = std::max(0.0, clean[k].stamp_s + s[k]);
    const auto [left, right] = ticksAt(clean, t);
    encoders[k] = {t, std::llround(left), std::llround(right)};
  }
  return jitterSummary(s);
}

/// What scan after scan was taken off its stamp (the run drew them: ScanReadJitter).
json scanReadRecord(const FaultsConfig& f, std::uint64_t seed, double lidar_hz, std::size_t scans) {
  ScanReadJitter draws(f, seed, lidar_hz);
  std::vector<double> e(scans);
  for (double& x : e) x = draws.next();
  json record = jitterSummary(e);
  record["errors_s"] = e;
  return record;
}

using TimeWindows = std::vector<std::pair<double, double>>;

/// Removes the encoder samples whose clean time falls into a dropout window and counts them
/// in the dropouts' record.
void removeEncoderDropouts(const TimeWindows& windows, double encoders_hz, EncoderLog& encoders,
                           json& record) {
  // The windows are in true time: undo nothing, a jittered stamp moves < half a period.
  EncoderLog kept;
  kept.reserve(encoders.size());
  const double period = 1.0 / encoders_hz;
  for (std::size_t k = 0; k < encoders.size(); ++k)
    if (!inWindow(windows, static_cast<double>(k) * period)) kept.push_back(encoders[k]);
  std::size_t i = 0;
  for (auto& event : record["events"]) {
    const auto& [from, to] = windows[i++];
    event["samples"] = static_cast<std::int64_t>(std::ceil(to * encoders_hz - 1e-9)) -
                       static_cast<std::int64_t>(std::ceil(from * encoders_hz - 1e-9));
  }
  record["removed"] = encoders.size() - kept.size();
  encoders = std::move(kept);
}

/// Encoders: read jitter, stale holds, spikes and stamp jitter by clean index, then the dropouts
/// removed.
void injectEncoderFaults(const FaultsConfig& f, std::uint64_t seed, const StreamRates& rates,
                         double duration_s, EncoderLog& encoders, json& out, json& jitter_record) {
  const FaultSet& on = f.enable;
  if (on.has(Fault::read_jitter)) {
    out["read_jitter"] = {{"encoders_sigma_s", f.read_jitter_encoders_sigma_s},
                          {"scans_sigma_s", f.read_jitter_scans_sigma_s}};
    if (f.read_jitter_encoders_correlation_s > 0.0)
      out["read_jitter"]["encoders_correlation_s"] = f.read_jitter_encoders_correlation_s;
    out["read_jitter"]["encoders"] = readOffStamps(f, seed, encoders);
  }
  if (on.has(Fault::stale_odometry))
    out["stale_odometry"] = holdEncoders(f, seed, duration_s, encoders);
  if (on.has(Fault::encoder_spikes))
    out["encoder_spikes"] = injectSpikes(f, seed, duration_s, encoders);
  TimeWindows windows;
  if (on.has(Fault::encoder_dropouts))
    out["encoder_dropouts"] = dropoutWindows(f, seed, duration_s, windows);
  if (on.has(Fault::stamp_jitter)) {
    const EncoderLog grid = encoders;
    if (f.stamp_jitter_encoders_sampling_sigma_s > 0.0)
      jitter_record["encoders_sampling"] = sampleOffGrid(f, seed, rates.encoders_hz, encoders);
    SplitMix64 rng = stream(seed, RngStream::fault_jitter_encoders);
    auto e = jitter(rng, encoders.size(), f.jitterSigma(f.stamp_jitter_encoders_sigma_s),
                    rates.encoders_hz);
    // Sampled off the grid and stamped off that, a sample stays within 0.45 periods of its grid
    // time as either alone keeps it: two draws could otherwise swap neighbours, and a log's
    // stamps do not run backwards.
    const double limit_s = 0.45 / rates.encoders_hz;
    for (std::size_t k = 0; k < e.size(); ++k) {
      const double offset = encoders[k].stamp_s - grid[k].stamp_s;
      e[k] = std::clamp(offset + e[k], -limit_s, limit_s) - offset;
      encoders[k].stamp_s += e[k];
    }
    jitter_record["encoders"] = jitterSummary(e);
  }
  if (!windows.empty())
    removeEncoderDropouts(windows, rates.encoders_hz, encoders, out["encoder_dropouts"]);
}

/// IMU: bias drift, then stamp jitter.
void injectImuFaults(const FaultsConfig& f, std::uint64_t seed, const StreamRates& rates,
                     ImuLog& imu, json& out, json& jitter_record) {
  const FaultSet& on = f.enable;
  if (on.has(Fault::imu_bias_drift)) out["imu_bias_drift"] = driftImu(f, seed, imu);
  if (on.has(Fault::stamp_jitter)) {
    SplitMix64 rng = stream(seed, RngStream::fault_jitter_imu);
    const auto e = jitter(rng, imu.size(), f.jitterSigma(f.stamp_jitter_imu_sigma_s), rates.imu_hz);
    for (std::size_t k = 0; k < e.size(); ++k) imu[k].stamp_s += e[k];
    jitter_record["imu"] = jitterSummary(e);
  }
}

/// Scans: beams, stamps (jitter + offset) by clean index, then whole scans dropped. The stamp
/// jitter record (with the encoders' and the IMU's) is written here, after the last stream.
void injectScanFaults(const FaultsConfig& f, std::uint64_t seed, const StreamRates& rates,
                      std::vector<ScanRecord>& scans, json& out, json& jitter_record) {
  const FaultSet& on = f.enable;
  if (on.has(Fault::read_jitter) && f.read_jitter_scans_sigma_s > 0.0)  // drawn in the run
    out["read_jitter"]["scans"] = scanReadRecord(f, seed, rates.lidar_hz, scans.size());
  if (on.has(Fault::dropped_beams)) out["dropped_beams"] = dropBeams(f, seed, scans);
  if (on.has(Fault::stamp_jitter)) {
    SplitMix64 rng = stream(seed, RngStream::fault_jitter_scans);
    const auto e =
        jitter(rng, scans.size(), f.jitterSigma(f.stamp_jitter_scans_sigma_s), rates.lidar_hz);
    for (std::size_t k = 0; k < e.size(); ++k) scans[k].scan.stamp_s += e[k];
    jitter_record["scans"] = jitterSummary(e);
    jitter_record["scan_stamp_errors_s"] = e;
    jitter_record["sigma_s"] = f.stamp_jitter_sigma_s;
    out["stamp_jitter"] = jitter_record;
  }
  if (on.has(Fault::clock_offset)) {
    for (ScanRecord& r : scans) r.scan.stamp_s += f.clock_offset_s;
    out["clock_offset"] = {{"offset_s", f.clock_offset_s}};
  }
  if (on.has(Fault::dropped_scans)) {
    json record;
    const std::vector<bool> dropped = droppedScans(f, seed, rates.lidar_hz, scans, record);
    std::vector<ScanRecord> kept;
    kept.reserve(scans.size());
    for (std::size_t k = 0; k < scans.size(); ++k)
      if (!dropped[k]) kept.push_back(std::move(scans[k]));
    scans = std::move(kept);
    out["dropped_scans"] = record;
  }
}

}  // namespace

json injectStreamFaults(const FaultsConfig& f, std::uint64_t seed, const StreamRates& rates,
                        double duration_s, Dataset& data) {
  json out = json::object();
  json jitter_record = json::object();
  injectEncoderFaults(f, seed, rates, duration_s, data.encoders, out, jitter_record);
  injectImuFaults(f, seed, rates, data.imu, out, jitter_record);
  injectScanFaults(f, seed, rates, data.scans, out, jitter_record);
  return out;
}

World worldWithFaults(const World& world, const FaultSet& faults) {
  World out = world;
  if (!faults.has(Fault::glass)) {
    for (Wall& o : out.walls) o.returns = true;
    for (Box& o : out.boxes) o.returns = true;
    for (Cylinder& o : out.cylinders) o.returns = true;
    for (Polygon& o : out.polygons) o.returns = true;
  }
  if (!faults.has(Fault::floor_patches)) out.floor_patches.clear();
  return out;
}

namespace {

// Which objects are glass: {"walls": [indices], "boxes": [...], ...}.
json glassRecord(const World& world) {
  auto indices = [](const auto& objects) {
    json out = json::array();
    for (std::size_t i = 0; i < objects.size(); ++i)
      if (!objects[i].returns) out.push_back(i);
    return out;
  };
  return {{"walls", indices(world.walls)},
          {"boxes", indices(world.boxes)},
          {"cylinders", indices(world.cylinders)},
          {"polygons", indices(world.polygons)}};
}

}  // namespace

json injectFaults(const SimConfig& config, const World& world, const FloorSlip* slip,
                  const HeldSchedule& held, double duration_s, Dataset& data) {
  const FaultsConfig& f = config.faults;
  const StreamRates rates{config.encoders.rate_hz, config.imu.rate_hz, config.lidar.rate_hz};
  json out = {{"enabled", json::array()}};
  for (const auto& [fault, name] : kFaultNames)
    if (f.enable.has(fault)) out["enabled"].push_back(name);
  out.update(injectStreamFaults(f, config.seed, rates, duration_s, data));
  if (f.enable.has(Fault::floor_patches)) {
    json record = slip ? slip->record() : json{{"patches", json::array()}};
    record["active"] = slip != nullptr;  // kinematic mode: the wheels never slip
    out["floor_patches"] = record;
  }
  if (f.enable.has(Fault::glass)) out["glass"] = glassRecord(world);
  if (f.enable.has(Fault::held_robot)) out["held_robot"] = held.record(f);
  return out;
}

}  // namespace slamprep::sim
