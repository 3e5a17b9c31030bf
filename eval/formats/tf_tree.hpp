#pragma once
// The tf tree of a bag (/tf and /tf_static, tf2_msgs/msg/TFMessage): parent -> child transforms
// composed along the tree, any number of hops, to find where the lidar sits on the base (in 3D),
// and that mount made planar: level, or upside down (a mirrored scan), else refused.

#include <Eigen/Geometry>
#include <map>
#include <optional>
#include <string>

#include "slamprep/core/se2.hpp"
#include "slamprep/eval/formats/ros2_messages.hpp"

namespace slamprep::eval {

/// A frame's path to another through the tree, and how much its dynamic edges moved.
struct TfPath {
  std::string frames;        ///< "base_link -> chassis -> laser"
  bool has_dynamic = false;  ///< an edge of the path came from /tf
  double motion_m = 0.0;     ///< largest move of an edge from its first value
  double motion_rad = 0.0;   ///< largest turn of an edge from its first value
};

class TfTree {
 public:
  /// One transform of /tf_static (`is_static`) or /tf. A frame has one parent (tf2's rule): a
  /// second parent is an InputError naming the frames. An edge keeps its first value and how
  /// far later values move from it (memory per edge, not per message).
  void add(const TransformStampedMsg& t, bool is_static, const std::string& where);

  bool empty() const { return edges_.empty(); }
  bool has(const std::string& frame) const;
  /// Every frame of the tree, sorted, for messages.
  std::string frameList() const;

  /// T_target_source (points of `source` into `target`), composed up to the frames' nearest
  /// common ancestor and down again; nullopt when they are not connected.
  std::optional<Eigen::Isometry3d> lookup(const std::string& target, const std::string& source,
                                          TfPath* path = nullptr) const;

 private:
  struct Edge {
    std::string parent;
    Eigen::Isometry3d T_parent_child = Eigen::Isometry3d::Identity();
    bool is_static = true;
    double motion_m = 0.0, motion_rad = 0.0;
  };
  /// T_ancestor_frame for `frame` and each of its ancestors, nearest first.
  std::vector<std::pair<std::string, Eigen::Isometry3d>> ancestors(const std::string& frame) const;

  std::map<std::string, Edge> edges_;  ///< by child frame
};

/// The lidar mount in the plane of the base.
struct PlanarMount {
  SE2 T_base_lidar;          ///< x, y and the yaw of the lidar's x axis
  bool upside_down = false;  ///< lidar z along -base z: beam angles are mirrored (a -> -a)
  double tilt_rad = 0.0;     ///< angle between the lidar's z axis and +-base z
  double height_m = 0.0;     ///< z of the lidar over the base (not used by 2D methods)
};

/// The planar mount of T_base_laser: level or upside down within `max_tilt_rad`; otherwise
/// InputError naming `frames` with the tilt, roll and pitch.
PlanarMount planarMount(const Eigen::Isometry3d& T_base_laser, const std::string& frames,
                        double max_tilt_rad);

}  // namespace slamprep::eval
