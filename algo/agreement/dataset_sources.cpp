#include "slamprep/algo/agreement/dataset_sources.hpp"

#include <cmath>

#include "slamprep/core/odometry.hpp"

namespace slamprep::algo {
namespace {

WheelTrack wheelTrack(const Dataset& d) {
  WheelTrack w;
  w.nominal = d.info.nominal_geometry;
  w.from = encodersFrom(d.info);
  const double rad_per_tick = radiansPerTick(d.info.ticks_per_revolution);
  w.phi_rad.reserve(d.encoders.size());
  for (const EncoderSample& e : d.encoders)
    w.phi_rad.push_back(e.stamp_s, Eigen::Vector2d(double(e.ticks_left) * rad_per_tick,
                                                   double(e.ticks_right) * rad_per_tick));
  return w;
}

/// The streams the clock sync moves, as logged.
struct ClockStreams {
  EncoderLog encoders;
  PoseSeries odometry;
  ImuLog imu;
};

}  // namespace

std::string encodersFrom(const DatasetInfo& info) {
  const nlohmann::json& c = info.config;
  if (c.is_object() && c.contains("encoders_from") && c["encoders_from"].is_string())
    return c["encoders_from"];
  const bool has_text = c.is_object() && c.contains("encoders") && c["encoders"].is_string();
  const std::string text = has_text ? c["encoders"].get<std::string>() : std::string();
  if (text.rfind("derived from", 0) == 0) return "odometry_poses";
  if (text.rfind("JointState", 0) == 0) return "joint_states";
  return "ticks";
}

RotationSources datasetSources(const Dataset& d, std::vector<HeadingSeries> scan_pieces) {
  RotationSources s;
  if (d.encoders.size() >= 2) s.wheels = wheelTrack(d);
  if (d.imu.size() >= 2) s.gyro = gyroHeading(d.imu);
  // The odometry topic is a source of its own only where the wheels were not derived from it:
  // the logged topic beside joint states, or a dataset odometry whose heading is the gyro's.
  const bool gyro_headed =
      d.info.config.is_object() && d.info.config.value("odometry_heading", "") == "gyro";
  const PoseSeries* topic = nullptr;
  if (!d.odometry_logged.empty() && (!s.wheels || s.wheels->from != "odometry_poses"))
    topic = &d.odometry_logged;
  else if ((!s.wheels || gyro_headed) && d.odom_nominal.size() >= 2)
    topic = &d.odom_nominal;
  if (topic) {
    s.odometry = poseHeading(*topic);
    s.odometry_travel = poseTravel(*topic);
  }
  s.scans = std::move(scan_pieces);
  return s;
}

std::vector<HeadingSeries> scanPieces(const std::vector<PoseSeries>& matched) {
  std::vector<HeadingSeries> pieces;
  for (const PoseSeries& p : matched) pieces.push_back(poseHeading(p));
  return pieces;
}

const PairAgreement* wheelsAgainstScans(const SensorAgreement& agreement) {
  const PairAgreement* wheels = agreement.pair("wheels", "scans");
  return wheels ? wheels : agreement.pair("odometry", "scans");
}

ClockShift scanClockShift(const SensorAgreement& agreement, double min_lag_s) {
  const PairAgreement* ws = wheelsAgainstScans(agreement);
  if (!ws || std::abs(ws->lag_s) <= min_lag_s) return {};
  const PairAgreement* gs = agreement.pair("gyro", "scans");
  return {ws->lag_s, gs && std::abs(gs->lag_s) > min_lag_s ? gs->lag_s : 0.0};
}

void shiftOntoScanClock(Dataset& dataset, const ClockShift& shift) {
  for (EncoderSample& e : dataset.encoders) e.stamp_s += shift.wheels_s;
  PoseSeries odometry;
  for (const auto& s : dataset.odom_nominal.samples())
    odometry.push_back(s.stamp_s + shift.wheels_s, s.value);
  dataset.odom_nominal = std::move(odometry);
  for (ImuSample& i : dataset.imu) i.stamp_s += shift.gyro_s;
}

double syncOntoScanClock(Dataset& dataset, const SensorAgreement& first, double min_lag_s,
                         double min_left_s, const MatchScans& match_again) {
  const ClockShift shift = scanClockShift(first, min_lag_s);
  if (!shift.any()) return 0.0;
  const ClockStreams logged{dataset.encoders, dataset.odom_nominal, dataset.imu};
  shiftOntoScanClock(dataset, shift);
  const std::vector<PoseSeries> matched = match_again(dataset);
  AgreementParams fine;
  fine.window_s = 1.0;
  fine.step_s = 0.25;
  fine.max_lag_s = 0.1;
  fine.lag_gain = 1.0;
  const ClockShift left = scanClockShift(
      compareSensors(datasetSources(dataset, scanPieces(matched)), fine), min_left_s);
  if (!left.any()) return shift.wheels_s;
  const double total_s = shift.wheels_s + left.wheels_s;
  if (std::abs(total_s) <= min_lag_s) {  // the second measure took the first back: no delay
    dataset.encoders = logged.encoders;
    dataset.odom_nominal = logged.odometry;
    dataset.imu = logged.imu;
    match_again(dataset);
    return 0.0;
  }
  shiftOntoScanClock(dataset, left);
  match_again(dataset);
  return total_s;
}

}  // namespace slamprep::algo
