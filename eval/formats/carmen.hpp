#pragma once
// Reading CARMEN logs (the text format of the CARMEN robot toolkit that CSM, GMapping and the
// Freiburg SLAM benchmark logs use): ODOM, PARAM and the laser messages ROBOTLASER1, FLASER,
// RLASER, RAWLASER1..4; '#' comments; every other message is counted and skipped.

#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "slamprep/core/laser_scan.hpp"
#include "slamprep/core/se2.hpp"

namespace slamprep::eval {

/// The laser messages. FLASER/RLASER (front/rear laser): laser and odometry pose, no angles.
/// ROBOTLASER1: angles, range limit, laser and robot pose. RAWLASER1..4: angles, no pose.
enum class CarmenLaserType {
  kRobotLaser1,
  kFlaser,
  kRlaser,
  kRawLaser1,
  kRawLaser2,
  kRawLaser3,
  kRawLaser4
};

/// The message name ("FLASER", ...); nullopt for a name that is not a laser message.
std::string_view carmenMessageName(CarmenLaserType type);
std::optional<CarmenLaserType> parseCarmenLaserType(std::string_view name);

/// One laser line: the scan (time_increment and scan_time 0: CARMEN has no such fields) and the
/// poses logged with it.
struct CarmenLaser {
  CarmenLaserType type = CarmenLaserType::kRobotLaser1;
  LaserScan scan;
  std::optional<SE2> T_odom_base;   ///< robot pose (FLASER/RLASER: odom_x odom_y odom_theta)
  std::optional<SE2> T_odom_laser;  ///< laser pose (FLASER/RLASER: x y theta)
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

struct CarmenReadParams {
  /// Stamps may run backwards within a stream (ODOM, or one laser message type) by up to this
  /// much; larger backward steps are refused.
  double reorder_tolerance_s = 0.05;
  /// What happens to a stream whose stamps ran backwards: false = sorted stably by stamp (for
  /// lines logged late); true = every line stamped at or after a later line of its stream is
  /// dropped, the file order kept (for lines stamped late, as in the Intel log).
  bool drop_late = false;
};

struct CarmenLog {
  std::map<std::string, CarmenParam> params;  ///< PARAM lines (the last one of a name wins)
  std::vector<CarmenOdom> odometry;           ///< sorted by stamp
  std::map<CarmenLaserType, std::vector<CarmenLaser>> lasers;  ///< per type, sorted by stamp
  /// Per message name: lines sorted into place (or dropped, with drop_late).
  std::map<std::string, std::size_t> out_of_order;
  /// Per message name: lines identical to the latest one of their stream (a message logged
  /// twice, as ODOM on line 14032 of the ACES log), dropped.
  std::map<std::string, std::size_t> repeated;
  std::map<std::string, std::size_t> skipped;  ///< other messages (SYNC, TRUEPOS, ...) by name
  std::size_t comment_lines = 0;
};

/// Parses a CARMEN log. Rejects, with InputError("file:line", "field: ..."): a wrong token
/// count, a non-number, NaN/Inf, a negative or zero max range, a beam count that is negative,
/// zero or larger than the tokens on the line, a field of view that disagrees with the
/// resolution and beam count, a stamp more than params.reorder_tolerance_s before an earlier one
/// of its stream (naming both lines and stamps), and (unless drop_late) duplicate stamps within
/// a stream, except on a line identical to the latest of its stream (dropped, counted).
CarmenLog parseCarmen(std::string_view text, const std::string& file,
                      const CarmenReadParams& params = {});

}  // namespace slamprep::eval
