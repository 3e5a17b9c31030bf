#include "slamprep/sim/drive/explore.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "slamprep/core/odometry.hpp"
#include "slamprep/sim/drive/controller.hpp"
#include "slamprep/sim/drive/free_space.hpp"
#include "slamprep/sim/drive/rng.hpp"
#include "slamprep/sim/drive/segment_shapes.hpp"

namespace slamprep::sim {
namespace {

constexpr double kReplayStep_s = 0.01;  // the path check's step (path_check.cpp)

/// The pose the commanded profile reaches from T_world_start, driven with the true geometry as
/// checkPathInWorld replays it.
SE2 replayEnd(const CommandProfile& profile, const SimConfig& config, const SE2& T_world_start) {
  const Controller controller(profile, config.nominalGeometry());
  SE2 T_world_base = T_world_start;
  const double end_s = profile.duration_s();
  const auto steps = static_cast<std::int64_t>(std::ceil(end_s / kReplayStep_s));
  for (std::int64_t k = 1; k <= steps; ++k) {
    const double t0 = (k - 1) * kReplayStep_s, t1 = std::min(end_s, k * kReplayStep_s);
    const Eigen::Vector2d dphi = controller.wheelAngleIncrement(t0, t1);
    T_world_base = T_world_base * wheelIncrement(config.robot.geometry, dphi.x(), dphi.y());
  }
  return T_world_base;
}

/// Pure pursuit along A* paths between random goals, simulated on the robot's true kinematics
/// (the controller's nominal J^-1, the true geometry's arcs), so the plan is the path the robot
/// will drive up to slip. Emits a twist knot every control period.
class Explorer {
 public:
  Explorer(const Scene& scene, const SimConfig& config, const ExploreParams& params,
           const SE2& T_world_start)
      : params_(params),
        nominal_(config.nominalGeometry()),
        truth_(config.robot.geometry),
        grid_(scene, footprintRadius(config.robot) + config.path_margin_m + params.clearance_m,
              params.grid_resolution_m, T_world_start.translation()),
        rng_(params.seed),
        T_world_base_(T_world_start) {}

  std::vector<CommandKnot> run() {
    const double dt = params_.control_period_s, end_s = params_.duration_s;
    std::vector<CommandKnot> knots{{0.0, Eigen::Vector2d::Zero()}};
    for (std::int64_t k = 1;; ++k) {
      const double t1 = static_cast<double>(k) * dt;
      const Eigen::Vector2d next = limited(target());
      // Accept the next command only if the robot can still come to rest by the end.
      if (end_s - t1 <= twistRamp(next, params_.limits)) break;
      drive(command_, next, dt);
      command_ = next;
      knots.push_back({t1, next});
    }
    knots.push_back({end_s, Eigen::Vector2d::Zero()});
    return knots;
  }

 private:
  /// The (v, w) pure pursuit asks for: the arc through the look-ahead point (curvature
  /// kappa = 2 y / d^2 in the base frame), slowed so |w| <= max; a turn on the spot while the
  /// point is more than 60 deg off the heading (until it is within 15 deg).
  Eigen::Vector2d target() {
    if (path_.empty() || atGoal()) newGoal();
    const Eigen::Vector2d p_base = T_world_base_.inverse() * lookahead();
    const double alpha = std::atan2(p_base.y(), p_base.x());
    turning_ = std::abs(alpha) > (turning_ ? std::numbers::pi / 12 : std::numbers::pi / 3);
    const double w_max = params_.max_turn_rate_radps;
    if (turning_) return {0.0, std::copysign(0.6 * w_max, alpha)};
    const double kappa = 2.0 * p_base.y() / std::max(p_base.squaredNorm(), 1e-6);
    const double v = std::min(cruise_mps_, w_max / std::max(std::abs(kappa), 1e-9));
    return {v, v * kappa};
  }

  /// Steps from the current command towards `wanted` within the acceleration limits; w follows
  /// the curvature at the speed actually reached, so slowing down does not widen the arc.
  Eigen::Vector2d limited(const Eigen::Vector2d& wanted) const {
    const double dv = params_.limits.linear_mps2 * params_.control_period_s;
    const double dw = params_.limits.angular_radps2 * params_.control_period_s;
    const double v = std::clamp(wanted.x(), command_.x() - dv, command_.x() + dv);
    const double w_at_v = wanted.x() > 1e-9 ? wanted.y() * v / wanted.x() : wanted.y();
    const double w = std::clamp(w_at_v, command_.y() - dw, command_.y() + dw);
    return {v, std::clamp(w, -params_.max_turn_rate_radps, params_.max_turn_rate_radps)};
  }

  /// Integrates one control period: twist linear from c0 to c1, wheel rates by the nominal J^-1,
  /// the base on the true geometry's arcs in the path check's steps.
  void drive(const Eigen::Vector2d& c0, const Eigen::Vector2d& c1, double dt) {
    const int n = std::max(1, static_cast<int>(std::lround(dt / kReplayStep_s)));
    const Eigen::Vector2d r0 = nominal_.wheelRates(c0.x(), c0.y());
    const Eigen::Vector2d r1 = nominal_.wheelRates(c1.x(), c1.y());
    for (int i = 0; i < n; ++i) {
      const double f0 = static_cast<double>(i) / n, f1 = static_cast<double>(i + 1) / n;
      const Eigen::Vector2d dphi = 0.5 * (dt / n) * ((r0 + f0 * (r1 - r0)) + (r0 + f1 * (r1 - r0)));
      T_world_base_ = T_world_base_ * wheelIncrement(truth_, dphi.x(), dphi.y());
    }
  }

  bool atGoal() const {
    return (path_.back() - T_world_base_.translation()).norm() < params_.lookahead_m;
  }

  /// A uniform random free cell at least min_goal_distance_m away (100 tries, then any), the A*
  /// path to it, and a uniform random cruise speed for the leg.
  void newGoal() {
    const Eigen::Vector2d p = T_world_base_.translation();
    const std::vector<int>& cells = grid_.freeCells();
    int goal = cells.front();
    for (int attempt = 0; attempt < 100; ++attempt) {
      goal = cells[std::min(cells.size() - 1,
                            static_cast<std::size_t>(rng_.uniform() * cells.size()))];
      if ((grid_.centre(goal) - p).norm() >= params_.min_goal_distance_m) break;
    }
    path_ = grid_.path(grid_.nearestFree(p), goal);
    progress_ = 0;
    cruise_mps_ =
        params_.min_speed_mps + (params_.max_speed_mps - params_.min_speed_mps) * rng_.uniform();
  }

  /// The first path point at least lookahead_m from the robot beyond the closest point so far
  /// (searched a few metres ahead, so a path that doubles back is not cut short).
  Eigen::Vector2d lookahead() {
    const Eigen::Vector2d p = T_world_base_.translation();
    const std::size_t window =
        progress_ + static_cast<std::size_t>(std::ceil(3.0 / params_.grid_resolution_m));
    for (std::size_t i = progress_; i < std::min(path_.size(), window); ++i)
      if ((path_[i] - p).squaredNorm() < (path_[progress_] - p).squaredNorm()) progress_ = i;
    for (std::size_t i = progress_; i < path_.size(); ++i)
      if ((path_[i] - p).norm() >= params_.lookahead_m) return path_[i];
    return path_.back();
  }

  const ExploreParams& params_;
  DiffDriveParams nominal_, truth_;
  FreeSpaceGrid grid_;
  SplitMix64 rng_;
  SE2 T_world_base_;
  Eigen::Vector2d command_ = Eigen::Vector2d::Zero();
  std::vector<Eigen::Vector2d> path_;
  std::size_t progress_ = 0;
  double cruise_mps_ = 0.0;
  bool turning_ = false;
};

}  // namespace

Scenario planExplore(const Scene& scene, const Scenario& scenario, const SimConfig& config,
                     const SE2& T_world_start) {
  Scenario planned = scenario;
  planned.profile = CommandProfile{};
  for (const ProfileSegment& segment : scenario.profile.segments()) {
    ProfileSegment copy = segment;
    if (segment.explore) {
      const SE2 T_world_base = replayEnd(planned.profile, config, T_world_start);
      copy.knots = Explorer(scene, config, *segment.explore, T_world_base).run();
      copy.explore.reset();
    }
    planned.profile.append(std::move(copy));
  }
  return planned;
}

}  // namespace slamprep::sim
