#pragma once
// Reading CARMEN logs (the text format of the CARMEN robot toolkit that CSM, GMapping and the
// Freiburg tools read): ODOM, ROBOTLASER1 and FLASER lines; every other message is skipped.

#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "core/laser_scan.hpp"
#include "core/se2.hpp"

namespace slamprep::eval {

/// One laser line: the scan (time_increment and scan_time 0: CARMEN has no such fields), the
/// robot odometry pose and the laser pose it was logged with.
struct CarmenLaser {
  LaserScan scan;
  SE2 T_odom_base;   ///< robot_pose (FLASER: the odometry pose)
  SE2 T_odom_laser;  ///< laser_pose (FLASER: the same pose as the laser one)
  std::size_t line = 0;
};

struct CarmenOdom {
  double stamp_s = 0.0;
  SE2 T_odom_base;
  std::size_t line = 0;
};

/// A `PARAM name value ...` line.
struct CarmenParam {
  std::string value;
  std::size_t line = 0;
};

struct CarmenLog {
  std::map<std::string, CarmenParam> params;  ///< PARAM lines (the last one of a name wins)
  std::vector<CarmenOdom> odometry;
  std::vector<CarmenLaser> lasers;
  std::size_t skipped_lines = 0;  ///< other message types (SYNC, TRUEPOS, ...)
};

/// Parses a CARMEN log. Rejects, with InputError("file:line", "field: ..."): a wrong token
/// count, a non-number, NaN/Inf, a negative or zero max range, a beam count that is negative,
/// zero or larger than the tokens on the line, a field of view that disagrees with the
/// resolution and beam count, and timestamps that do not increase strictly within ODOM lines
/// or within laser lines.
CarmenLog parseCarmen(std::string_view text, const std::string& file);

}  // namespace slamprep::eval
