#include "slamprep/sim/drive/command_profile.hpp"

#include <algorithm>

namespace slamprep::sim {

namespace detail {
Eigen::Vector2d valueAt(const ProfileSegment& segment, double t_s) {
  const auto& knots = segment.knots;
  if (t_s <= knots.front().t_s || t_s >= knots.back().t_s) return Eigen::Vector2d::Zero();
  auto upper = std::upper_bound(knots.begin(), knots.end(), t_s,
                                [](double t, const CommandKnot& k) { return t < k.t_s; });
  const CommandKnot& b = *upper;
  const CommandKnot& a = *(upper - 1);
  const double f = (t_s - a.t_s) / (b.t_s - a.t_s);  // b.t_s > a.t_s: knots increase strictly
  return a.value + f * (b.value - a.value);
}
}  // namespace detail

void CommandProfile::append(ProfileSegment segment) {
  const double shift = duration_s() - segment.knots.front().t_s;
  for (CommandKnot& knot : segment.knots) knot.t_s += shift;
  segments_.push_back(std::move(segment));
}

void CommandProfile::append(const CommandProfile& other) {
  for (const ProfileSegment& segment : other.segments_) append(segment);
}

const ProfileSegment* CommandProfile::segmentAt(double t_s) const {
  auto it = std::upper_bound(segments_.begin(), segments_.end(), t_s,
                             [](double t, const ProfileSegment& s) { return t < s.start_s(); });
  if (it == segments_.begin()) return nullptr;
  const ProfileSegment& segment = *(it - 1);
  return t_s <= segment.end_s() ? &segment : nullptr;
}

Command CommandProfile::at(double t_s) const {
  const ProfileSegment* segment = segmentAt(t_s);
  if (segment == nullptr) return {};
  return {segment->kind, detail::valueAt(*segment, t_s)};
}

}  // namespace slamprep::sim
