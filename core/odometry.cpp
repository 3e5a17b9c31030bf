#include "slamprep/core/odometry.hpp"

#include <numbers>

namespace slamprep {

double radiansPerTick(int ticks_per_revolution) {
  return 2.0 * std::numbers::pi / ticks_per_revolution;
}

SE2 wheelIncrement(const DiffDriveParams& geometry, double dphi_left_rad, double dphi_right_rad) {
  const Eigen::Vector2d ds = geometry.twist(dphi_left_rad, dphi_right_rad);  // (v dt, w dt)
  return SE2::exp({ds.x(), 0.0, ds.y()});
}

PoseSeries integrateEncoders(const EncoderLog& encoders, const DiffDriveParams& geometry,
                             int ticks_per_revolution, const SE2& T_odom_base0) {
  PoseSeries odometry;
  if (encoders.empty()) return odometry;
  const double rad_per_tick = radiansPerTick(ticks_per_revolution);
  SE2 T_odom_base = T_odom_base0;
  odometry.push_back(encoders.front().stamp_s, T_odom_base);
  for (std::size_t k = 1; k < encoders.size(); ++k) {
    const auto& prev = encoders[k - 1];
    const auto& cur = encoders[k];
    T_odom_base =
        T_odom_base * wheelIncrement(geometry, (cur.ticks_left - prev.ticks_left) * rad_per_tick,
                                     (cur.ticks_right - prev.ticks_right) * rad_per_tick);
    odometry.push_back(cur.stamp_s, T_odom_base);
  }
  return odometry;
}

std::optional<SE2> anchorOnTruth(const PoseSeries& odometry, const PoseSeries& truth) {
  if (odometry.empty()) return std::nullopt;
  const std::optional<SE2> T_world_base0 = truth.at(odometry.frontStamp());
  if (!T_world_base0) return std::nullopt;
  return *T_world_base0 * odometry[0].value.inverse();
}

PoseSeries inWorld(const PoseSeries& odometry, const SE2& T_world_odom) {
  PoseSeries world;
  for (const auto& s : odometry.samples()) world.push_back(s.stamp_s, T_world_odom * s.value);
  return world;
}

}  // namespace slamprep
