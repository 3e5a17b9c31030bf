#include "slamprep/sim/drive/controller.hpp"

#include <algorithm>

namespace slamprep::sim {

Controller::Controller(const CommandProfile& profile, const DiffDriveParams& nominal_geometry)
    : profile_(&profile), nominal_(nominal_geometry) {
  for (const ProfileSegment& segment : profile.segments()) {
    double cap = 0.0;
    if (segment.closed_loop) {
      closed_loop_ = true;
      cap = segment.closed_loop->max_wheel_radps;
      // No cap given: the fastest wheel the commands turn (the knots are what they are).
      if (cap <= 0.0)
        for (const CommandKnot& knot : segment.knots)
          cap = std::max(cap, toWheelRates({segment.kind, knot.value}).cwiseAbs().maxCoeff());
    }
    cap_radps_.push_back(cap);
  }
}

Eigen::Vector2d Controller::wheelRates(double t_s, const SE2& T_world_base,
                                       const SE2& T_world_reference) const {
  const ProfileSegment* segment = profile_->segmentAt(t_s);
  if (segment == nullptr || !segment->closed_loop) return wheelRates(t_s);
  const Eigen::Vector2d feed_forward =
      toWheelRates({segment->kind, detail::valueAt(*segment, t_s)});
  const Eigen::Vector2d reference_twist = nominal_.twist(feed_forward.x(), feed_forward.y());
  const Eigen::Vector2d twist =
      trackingTwist(T_world_base, T_world_reference, reference_twist, *segment->closed_loop);
  const auto index = static_cast<std::size_t>(segment - profile_->segments().data());
  return capWheelRates(nominal_.wheelRates(twist.x(), twist.y()), cap_radps_[index]);
}

}  // namespace slamprep::sim
