#include "slamprep/eval/formats/ros2_params.hpp"

#include <yaml-cpp/yaml.h>

#include <sstream>
#include <string>

namespace slamprep::eval {
namespace {

// Shortest text that reads back to the same double.
std::string exact(double v) {
  for (int digits = 6;; ++digits) {
    std::ostringstream s;
    s.precision(digits);
    s << v;
    if (digits >= 17 || std::stod(s.str()) == v) return s.str();
  }
}

}  // namespace

std::string formatRos2Params(const Ros2ParamsInput& in) {
  // The controller multiplies: r_L = wheel_radius * left_wheel_radius_multiplier,
  // r_R = wheel_radius * right_wheel_radius_multiplier, b = wheel_separation * multiplier.
  const double radius = 0.5 * (in.nominal.radius_left_m + in.nominal.radius_right_m);
  YAML::Emitter out;
  out << YAML::BeginMap;
  out << YAML::Key << "diff_drive_controller" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "ros__parameters" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "wheel_separation" << YAML::Value << exact(in.nominal.wheel_base_m);
  out << YAML::Key << "wheel_radius" << YAML::Value << exact(radius);
  out << YAML::Key << "wheel_separation_multiplier" << YAML::Value
      << exact(in.calibrated.wheel_base_m / in.nominal.wheel_base_m);
  out << YAML::Key << "left_wheel_radius_multiplier" << YAML::Value
      << exact(in.calibrated.radius_left_m / radius);
  out << YAML::Key << "right_wheel_radius_multiplier" << YAML::Value
      << exact(in.calibrated.radius_right_m / radius);
  out << YAML::EndMap << YAML::EndMap;
  const SE2& l = in.T_base_lidar;
  out << YAML::Key << "base_link_to_laser" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "ros__parameters" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "frame_id" << YAML::Value << "base_link";
  out << YAML::Key << "child_frame_id" << YAML::Value << "laser";
  for (const auto& [key, value] : {std::pair<const char*, double>{"x", l.x},
                                   {"y", l.y},
                                   {"z", 0.0},
                                   {"roll", 0.0},
                                   {"pitch", 0.0},
                                   {"yaw", l.yaw}})
    out << YAML::Key << key << YAML::Value << exact(value);
  out << YAML::Key << "arguments" << YAML::Value << YAML::Flow << YAML::BeginSeq;
  for (const std::string& a :
       {std::string("--x"), exact(l.x), std::string("--y"), exact(l.y), std::string("--z"),
        std::string("0"), std::string("--roll"), std::string("0"), std::string("--pitch"),
        std::string("0"), std::string("--yaw"), exact(l.yaw), std::string("--frame-id"),
        std::string("base_link"), std::string("--child-frame-id"), std::string("laser")})
    out << a;
  out << YAML::EndSeq << YAML::EndMap << YAML::EndMap << YAML::EndMap;

  std::ostringstream text;
  text << "# slamprep calibrate --ros2-params (docs/calibration.md, \"ROS 2 parameters\").\n"
       << "# Wheel geometry from method " << in.method
       << ": r_L = wheel_radius * left_wheel_radius_multiplier = " << in.calibrated.radius_left_m
       << " m, r_R = " << in.calibrated.radius_right_m
       << " m, b = wheel_separation * wheel_separation_multiplier = " << in.calibrated.wheel_base_m
       << " m.\n";
  if (in.relative_to_odometry)
    text << "# The log had no encoder ticks: wheel_radius and wheel_separation are the nominal\n"
         << "# geometry the increments were derived with, not the robot's; only the three\n"
         << "# multipliers mean something: apply them to the robot's own configuration.\n";
  text << "# Lidar mount " << (in.mount_calibrated ? "calibrated" : "from dataset.json")
       << "; base_link_to_laser.arguments is the argument list of\n"
       << "# `ros2 run tf2_ros static_transform_publisher` (a launch Node's arguments=).\n"
       << out.c_str() << "\n";
  return text.str();
}

}  // namespace slamprep::eval
