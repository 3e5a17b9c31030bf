#include "eval/formats/carmen.hpp"

#include <cmath>
#include <numbers>

#include "core/error.hpp"
#include "eval/formats/text_io.hpp"

namespace slamprep::eval {
namespace {

using slamprep::eval::TextLocation;

class Tokens {
 public:
  Tokens(const std::vector<std::string_view>& t, const TextLocation& where)
      : t_(t), where_(where) {}

  std::string_view next(std::string_view field) {
    if (i_ >= t_.size())
      throw InputError(where_.str(), std::string(field) + ": missing (line has only " +
                                         std::to_string(t_.size()) + " fields)");
    return t_[i_++];
  }
  double number(std::string_view field) {
    return slamprep::eval::parseFiniteDouble(next(field), where_, field);
  }
  std::int64_t integer(std::string_view field) {
    return slamprep::eval::parseInt64(next(field), where_, field);
  }
  SE2 pose(std::string_view field) {
    const double x = number(std::string(field) + "_x");
    const double y = number(std::string(field) + "_y");
    const double th = number(std::string(field) + "_theta");
    return {x, y, th};
  }
  std::size_t left() const { return t_.size() - i_; }
  /// A count that must fit in the tokens left on the line (so 1e9 beams cannot allocate).
  std::size_t count(std::string_view field, std::size_t tokens_after) {
    const std::int64_t n = integer(field);
    if (n < 0)
      throw InputError(where_.str(), std::string(field) + ": negative (" + std::to_string(n) + ")");
    if (static_cast<std::uint64_t>(n) + tokens_after > left())
      throw InputError(where_.str(), std::string(field) + ": " + std::to_string(n) +
                                         " values announced but the line has only " +
                                         std::to_string(left()) + " fields left");
    return static_cast<std::size_t>(n);
  }
  /// hostname and logger_timestamp close every line; both are optional in practice.
  void finish() {
    if (left() > 2)
      throw InputError(where_.str(), "trailing fields: " + std::to_string(left()) +
                                         " more than hostname and logger_timestamp");
  }

 private:
  const std::vector<std::string_view>& t_;
  const TextLocation& where_;
  std::size_t i_ = 1;
};

void readRanges(Tokens& tok, LaserScan& scan, std::size_t n, const TextLocation& where) {
  scan.ranges_m.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double r = tok.number("range_readings");
    if (r < 0)
      throw InputError(where.str(), "range_readings: beam " + std::to_string(i) + " is negative");
    // CARMEN's "no return" is a reading at (or beyond) the maximum range.
    scan.ranges_m[i] = r >= scan.range_max_m ? std::numeric_limits<double>::infinity() : r;
  }
}

CarmenLaser parseRobotLaser(Tokens& tok, const TextLocation& where) {
  CarmenLaser l;
  tok.integer("laser_type");
  const double start = tok.number("start_angle");
  const double fov = tok.number("field_of_view");
  const double res = tok.number("angular_resolution");
  const double max_range = tok.number("maximum_range");
  tok.number("accuracy");
  tok.integer("remission_mode");
  if (max_range <= 0) throw InputError(where.str(), "maximum_range: must be > 0");
  if (res <= 0) throw InputError(where.str(), "angular_resolution: must be > 0");
  // After the readings: num_remissions, 6 pose values, 5 velocities/safety, timestamp.
  const std::size_t n = tok.count("num_readings", 1 + 6 + 5 + 1);
  if (n == 0) throw InputError(where.str(), "num_readings: empty scan (0 beams)");
  // Two conventions exist: fov = (n-1) res (beam centres) and fov = n res (coverage).
  const double span = res * double(n - 1);
  if (std::abs(fov - span) > res * 1.01)
    throw InputError(where.str(), "field_of_view: " + std::to_string(fov) + " rad disagrees with " +
                                      std::to_string(n) + " beams of " + std::to_string(res) +
                                      " rad");
  l.scan.angle_min_rad = start;
  l.scan.angle_increment_rad = res;
  l.scan.range_min_m = 0.0;
  l.scan.range_max_m = max_range;
  readRanges(tok, l.scan, n, where);
  const std::size_t n_rem = tok.count("num_remissions", 6 + 5 + 1);
  for (std::size_t i = 0; i < n_rem; ++i) tok.number("remissions");
  l.T_odom_laser = tok.pose("laser_pose");
  l.T_odom_base = tok.pose("robot_pose");
  for (const char* f :
       {"laser_tv", "laser_rv", "forward_safety_dist", "side_safety_dist", "turn_axis"})
    tok.number(f);
  l.scan.stamp_s = tok.number("timestamp");
  tok.finish();
  return l;
}

// FLASER num_readings [ranges] x y theta odom_x odom_y odom_theta timestamp hostname logger_ts.
// It carries no angles: like CARMEN's own reader, assume a SICK LMS starting at -90 degrees, with
// 1 degree between beams for 180/181 beams, 0.5 degree for 360/361, otherwise 180 degrees over
// the beams, and an 80 m maximum range.
CarmenLaser parseFlaser(Tokens& tok, const TextLocation& where) {
  CarmenLaser l;
  const std::size_t n = tok.count("num_readings", 6 + 1);
  if (n < 2) throw InputError(where.str(), "num_readings: need at least 2 beams");
  l.scan.angle_min_rad = -std::numbers::pi / 2;
  const double degree = std::numbers::pi / 180;
  l.scan.angle_increment_rad = (n == 180 || n == 181)   ? degree
                               : (n == 360 || n == 361) ? degree / 2
                                                        : std::numbers::pi / double(n - 1);
  l.scan.range_max_m = 80.0;
  readRanges(tok, l.scan, n, where);
  l.T_odom_laser = tok.pose("laser_pose");
  l.T_odom_base = tok.pose("odom_pose");
  l.scan.stamp_s = tok.number("timestamp");
  tok.finish();
  return l;
}

}  // namespace

CarmenLog parseCarmen(std::string_view text, const std::string& file) {
  CarmenLog log;
  slamprep::eval::LineCursor cursor(text);
  std::string_view line;
  std::vector<std::string_view> fields;
  TextLocation where{file, 0};
  while (cursor.next(line)) {
    where.line = cursor.lineNumber();
    slamprep::eval::splitWhitespace(line, fields);
    if (fields.empty() || fields[0].starts_with('#')) continue;
    Tokens tok(fields, where);
    if (fields[0] == "ODOM") {
      CarmenOdom o;
      const double x = tok.number("x");
      const double y = tok.number("y");
      o.T_odom_base = SE2(x, y, tok.number("theta"));
      for (const char* f : {"tv", "rv", "accel"}) tok.number(f);
      o.stamp_s = tok.number("timestamp");
      tok.finish();
      o.line = where.line;
      if (!log.odometry.empty())
        slamprep::eval::requireIncreasing(log.odometry.back().stamp_s, o.stamp_s, where,
                                          "timestamp");
      log.odometry.push_back(o);
    } else if (fields[0] == "ROBOTLASER1" || fields[0] == "FLASER") {
      CarmenLaser l = fields[0] == "FLASER" ? parseFlaser(tok, where) : parseRobotLaser(tok, where);
      l.line = where.line;
      if (!log.lasers.empty())
        slamprep::eval::requireIncreasing(log.lasers.back().scan.stamp_s, l.scan.stamp_s, where,
                                          "timestamp");
      log.lasers.push_back(std::move(l));
    } else if (fields[0] == "PARAM" && fields.size() >= 3) {
      log.params[std::string(fields[1])] = {std::string(fields[2]), where.line};
    } else {
      ++log.skipped_lines;
    }
  }
  return log;
}

}  // namespace slamprep::eval
