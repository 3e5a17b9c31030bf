#include "slamprep/eval/formats/tf_tree.hpp"

#include <cmath>
#include <numbers>
#include <set>
#include <vector>

#include "slamprep/core/error.hpp"

namespace slamprep::eval {
namespace {

std::string degrees(double rad) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2f deg", rad * 180.0 / std::numbers::pi);
  return text;
}

Eigen::Isometry3d isometry(const TransformStampedMsg& t, const std::string& where) {
  const auto& q = t.rotation;
  for (double v : {t.translation[0], t.translation[1], t.translation[2], q.x, q.y, q.z, q.w})
    if (!std::isfinite(v))
      throw InputError(
          where, "transform " + t.header.frame_id + " -> " + t.child_frame_id + ": not finite");
  Eigen::Quaterniond rotation(q.w, q.x, q.y, q.z);
  if (rotation.norm() < 1e-9)
    throw InputError(
        where, "transform " + t.header.frame_id + " -> " + t.child_frame_id + ": zero quaternion");
  rotation.normalize();
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = rotation.toRotationMatrix();
  T.translation() = Eigen::Vector3d(t.translation[0], t.translation[1], t.translation[2]);
  return T;
}

}  // namespace

void TfTree::add(const TransformStampedMsg& t, bool is_static, const std::string& where) {
  const std::string& parent = t.header.frame_id;
  const std::string& child = t.child_frame_id;
  if (parent.empty() || child.empty() || parent == child)
    throw InputError(where, "transform \"" + parent + "\" -> \"" + child +
                                "\": needs two different, non-empty frame names");
  const Eigen::Isometry3d T = isometry(t, where);
  auto [it, inserted] = edges_.try_emplace(child);
  Edge& e = it->second;
  if (inserted) {
    e.parent = parent;
    e.T_parent_child = T;
    e.is_static = is_static;
    return;
  }
  if (e.parent != parent)
    throw InputError(where, "frame " + child + " has two parents, " + e.parent + " and " + parent +
                                " (tf allows one)");
  e.is_static = e.is_static && is_static;
  const Eigen::Isometry3d d = e.T_parent_child.inverse() * T;
  e.motion_m = std::max(e.motion_m, d.translation().norm());
  e.motion_rad = std::max(e.motion_rad, Eigen::AngleAxisd(d.linear()).angle());
}

bool TfTree::has(const std::string& frame) const {
  if (edges_.count(frame)) return true;
  for (const auto& [child, e] : edges_)
    if (e.parent == frame) return true;
  return false;
}

std::string TfTree::frameList() const {
  std::set<std::string> frames;
  for (const auto& [child, e] : edges_) frames.insert({child, e.parent});
  std::string out;
  for (const auto& f : frames) out += (out.empty() ? "" : ", ") + f;
  return out;
}

std::vector<std::pair<std::string, Eigen::Isometry3d>> TfTree::ancestors(
    const std::string& frame) const {
  std::vector<std::pair<std::string, Eigen::Isometry3d>> out{
      {frame, Eigen::Isometry3d::Identity()}};
  std::set<std::string> seen{frame};
  for (auto it = edges_.find(frame); it != edges_.end(); it = edges_.find(it->second.parent)) {
    const Edge& e = it->second;
    if (!seen.insert(e.parent).second)
      throw InputError("tf", "frames form a cycle through " + e.parent);
    out.emplace_back(e.parent, e.T_parent_child * out.back().second);
  }
  return out;
}

std::optional<Eigen::Isometry3d> TfTree::lookup(const std::string& target,
                                                const std::string& source, TfPath* path) const {
  const auto up_source = ancestors(source), up_target = ancestors(target);
  for (std::size_t i = 0; i < up_target.size(); ++i)
    for (std::size_t j = 0; j < up_source.size(); ++j) {
      if (up_target[i].first != up_source[j].first) continue;
      // T_target_source = T_common_target^-1 T_common_source.
      if (path) {
        *path = {};
        auto visit = [&](const std::string& frame) {
          path->frames += (path->frames.empty() ? "" : " -> ") + frame;
        };
        auto edge = [&](const std::string& child) {
          const Edge& e = edges_.at(child);
          path->has_dynamic = path->has_dynamic || !e.is_static;
          path->motion_m = std::max(path->motion_m, e.motion_m);
          path->motion_rad = std::max(path->motion_rad, e.motion_rad);
        };
        for (std::size_t k = 0; k <= i; ++k) visit(up_target[k].first);
        for (std::size_t k = 0; k < i; ++k) edge(up_target[k].first);
        for (std::size_t k = j; k-- > 0;) {
          visit(up_source[k].first);
          edge(up_source[k].first);
        }
      }
      return up_target[i].second.inverse() * up_source[j].second;
    }
  return std::nullopt;
}

PlanarMount planarMount(const Eigen::Isometry3d& T_base_laser, const std::string& frames,
                        double max_tilt_rad) {
  const Eigen::Matrix3d R = T_base_laser.linear();
  PlanarMount m;
  m.upside_down = R(2, 2) < 0;
  // Angle between the lidar's z axis (R's third column) and +z, or -z when upside down.
  m.tilt_rad = std::acos(std::min(1.0, std::abs(R(2, 2))));
  if (m.tilt_rad > max_tilt_rad) {
    const double roll = std::atan2(R(2, 1), R(2, 2));
    const double pitch = std::asin(std::clamp(-R(2, 0), -1.0, 1.0));
    throw InputError("tf " + frames, "the lidar's scan plane is tilted " + degrees(m.tilt_rad) +
                                         " from the base plane (roll " + degrees(roll) +
                                         ", pitch " + degrees(pitch) +
                                         "); only level or upside-down mounts within " +
                                         degrees(max_tilt_rad) + " are read as 2D scans");
  }
  // The lidar's x axis, projected on the base plane, gives the yaw in both cases: a level mount
  // is Rz(yaw), an upside-down one Rz(yaw) Rx(pi), which maps the beam at angle a to yaw - a.
  const Eigen::Vector3d t = T_base_laser.translation();
  m.T_base_lidar = SE2(t.x(), t.y(), std::atan2(R(1, 0), R(0, 0)));
  m.height_m = t.z();
  return m;
}

}  // namespace slamprep::eval
