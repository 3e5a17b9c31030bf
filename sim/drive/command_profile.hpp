#pragma once
// The commanded motion over time: rest-to-rest segments of piecewise-linear twist or wheel-rate
// knots, concatenated into a CommandProfile that the controller samples and integrates.

#include <Eigen/Core>
#include <algorithm>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "slamprep/core/enum_names.hpp"
#include "slamprep/sim/drive/tracking_law.hpp"

namespace slamprep::sim {

struct ExploreParams;  // sim/drive/explore.hpp

/// What a command sets: the body twist (v, w) or the two wheel rates directly.
enum class CommandKind { twist, wheel_rates };
/// As a `track` segment's `kind` spells them.
inline constexpr auto kCommandKindNames = std::to_array<EnumName<CommandKind>>({
    {CommandKind::twist, "twist"},
    {CommandKind::wheel_rates, "wheel_rates"},
});

/// One commanded value. For `twist`: (v_mps, w_radps); for `wheel_rates`: (left, right) in rad/s.
struct Command {
  CommandKind kind = CommandKind::twist;
  Eigen::Vector2d value = Eigen::Vector2d::Zero();
};

/// Acceleration limits every segment's ramps respect.
struct AccelerationLimits {
  double linear_mps2 = 1.0;     ///< |dv/dt| for twist segments
  double angular_radps2 = 2.0;  ///< |dw/dt| for twist segments
  double wheel_radps2 = 10.0;   ///< |d(wheel rate)/dt| for wheel-rate segments
};

/// A time-stamped command value; commands are linear between consecutive knots of one segment.
struct CommandKnot {
  double t_s = 0.0;
  Eigen::Vector2d value = Eigen::Vector2d::Zero();
};

/// One rest-to-rest piece of the profile.
struct ProfileSegment {
  std::string type;   ///< segment type as written in the file ("straight", "arc", ...)
  std::string where;  ///< "file:line: segments[k]" for error messages
  CommandKind kind = CommandKind::twist;
  std::vector<CommandKnot> knots;  ///< absolute times, first and last value zero, >= 2 knots
  /// An `explore` segment before planning: its knots are a stop of the same length until
  /// planExplore (sim/drive/explore.hpp) replaces them with a path through the world.
  std::shared_ptr<const ExploreParams> explore;
  /// A `track` segment driven in closed loop (physics mode): its knots are the feed-forward,
  /// corrected by the robot's error from the kinematic replay of the commands (tracking_law.hpp).
  std::optional<TrackingParams> closed_loop;

  double start_s() const { return knots.front().t_s; }
  double end_s() const { return knots.back().t_s; }
};

/// The commanded profile over time: consecutive rest-to-rest segments, zero outside them.
class CommandProfile {
 public:
  /// Appends a segment given in local time (first knot at t = 0); it starts where the last ended.
  void append(ProfileSegment segment);
  /// Appends all segments of `other`, shifted to start where this profile ends.
  void append(const CommandProfile& other);

  double duration_s() const { return segments_.empty() ? 0.0 : segments_.back().end_s(); }
  const std::vector<ProfileSegment>& segments() const { return segments_; }
  /// The command at time t (zero twist before the start and after the end).
  Command at(double t_s) const;
  /// The segment active at time t, or nullptr outside the profile.
  const ProfileSegment* segmentAt(double t_s) const;

  /// Calls fn(kind, c0, c1, dt) for every linear piece overlapping [t0, t1], with the command
  /// values c0 at its start and c1 at its end: exact integration of the piecewise-linear profile.
  template <typename Fn>
  void forEachPiece(double t0_s, double t1_s, Fn&& fn) const;

 private:
  std::vector<ProfileSegment> segments_;
};

// ---------------------------------------------------------------------------------------------

namespace detail {
Eigen::Vector2d valueAt(const ProfileSegment& segment, double t_s);
}  // namespace detail

template <typename Fn>
void CommandProfile::forEachPiece(double t0_s, double t1_s, Fn&& fn) const {
  for (const ProfileSegment& segment : segments_) {
    if (segment.end_s() <= t0_s) continue;
    if (segment.start_s() >= t1_s) break;
    // From the piece holding t0 on (a long track has thousands of knots; the earlier pieces
    // would all be empty), until the pieces start after t1.
    const auto& knots = segment.knots;
    const auto after = std::upper_bound(knots.begin(), knots.end(), t0_s,
                                        [](double t, const CommandKnot& k) { return t < k.t_s; });
    const auto first =
        static_cast<std::size_t>(std::max<std::ptrdiff_t>(0, after - knots.begin() - 1));
    for (std::size_t k = first; k + 1 < knots.size() && knots[k].t_s < t1_s; ++k) {
      const double a = std::max(t0_s, segment.knots[k].t_s);
      const double b = std::min(t1_s, segment.knots[k + 1].t_s);
      if (b <= a) continue;
      fn(segment.kind, detail::valueAt(segment, a), detail::valueAt(segment, b), b - a);
    }
  }
}

}  // namespace slamprep::sim
