#include "slamprep/eval/formats/carmen.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

#include "slamprep/core/enum_names.hpp"
#include "slamprep/core/error.hpp"
#include "slamprep/eval/formats/text_io.hpp"

namespace slamprep::eval {
namespace {

constexpr auto kLaserNames = std::to_array<EnumName<CarmenLaserType>>({
    {CarmenLaserType::kRobotLaser1, "ROBOTLASER1"},
    {CarmenLaserType::kFlaser, "FLASER"},
    {CarmenLaserType::kRlaser, "RLASER"},
    {CarmenLaserType::kRawLaser1, "RAWLASER1"},
    {CarmenLaserType::kRawLaser2, "RAWLASER2"},
    {CarmenLaserType::kRawLaser3, "RAWLASER3"},
    {CarmenLaserType::kRawLaser4, "RAWLASER4"},
});

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
  double number(std::string_view field) { return parseFiniteDouble(next(field), where_, field); }
  std::int64_t integer(std::string_view field) { return parseInt64(next(field), where_, field); }
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

// laser_type start_angle fov angular_res max_range accuracy remission_mode num_readings
// [ranges] num_remissions [remissions]: ROBOTLASER1 and RAWLASERn share this head.
// `tokens_after` counts the fields after the remissions.
LaserScan parseLaserHead(Tokens& tok, std::size_t tokens_after, const TextLocation& where) {
  LaserScan scan;
  tok.integer("laser_type");
  const double start = tok.number("start_angle");
  const double fov = tok.number("field_of_view");
  const double res = tok.number("angular_resolution");
  const double max_range = tok.number("maximum_range");
  tok.number("accuracy");
  tok.integer("remission_mode");
  if (max_range <= 0) throw InputError(where.str(), "maximum_range: must be > 0");
  if (res <= 0) throw InputError(where.str(), "angular_resolution: must be > 0");
  const std::size_t n = tok.count("num_readings", 1 + tokens_after);
  if (n == 0) throw InputError(where.str(), "num_readings: empty scan (0 beams)");
  // Two conventions exist: fov = (n-1) res (beam centres) and fov = n res (coverage).
  const double span = res * double(n - 1);
  if (std::abs(fov - span) > res * 1.01)
    throw InputError(where.str(), "field_of_view: " + std::to_string(fov) + " rad disagrees with " +
                                      std::to_string(n) + " beams of " + std::to_string(res) +
                                      " rad");
  scan.angle_min_rad = start;
  scan.angle_increment_rad = res;
  scan.range_min_m = 0.0;
  scan.range_max_m = max_range;
  readRanges(tok, scan, n, where);
  const std::size_t n_rem = tok.count("num_remissions", tokens_after);
  for (std::size_t i = 0; i < n_rem; ++i) tok.number("remissions");
  return scan;
}

// ROBOTLASER1 head, laser_pose, robot_pose, tv rv forward_safety side_safety turn_axis, timestamp.
CarmenLaser parseRobotLaser(Tokens& tok, const TextLocation& where) {
  CarmenLaser l;
  l.scan = parseLaserHead(tok, 6 + 5 + 1, where);
  l.T_odom_laser = tok.pose("laser_pose");
  l.T_odom_base = tok.pose("robot_pose");
  for (const char* f :
       {"laser_tv", "laser_rv", "forward_safety_dist", "side_safety_dist", "turn_axis"})
    tok.number(f);
  l.scan.stamp_s = tok.number("timestamp");
  return l;
}

// RAWLASERn head, timestamp: the scan alone.
CarmenLaser parseRawLaser(Tokens& tok, const TextLocation& where) {
  CarmenLaser l;
  l.scan = parseLaserHead(tok, 1, where);
  l.scan.stamp_s = tok.number("timestamp");
  return l;
}

// FLASER/RLASER num_readings [ranges] x y theta odom_x odom_y odom_theta timestamp. No angles:
// like CARMEN's own reader and GMapping's, assume a SICK LMS starting at -90 degrees, 1 degree
// between beams for 180/181 beams, 0.5 degree for 360/361, otherwise 180 degrees over the beams,
// and an 80 m maximum range.
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
  return l;
}

CarmenLaser parseLaser(CarmenLaserType type, Tokens& tok, const TextLocation& where) {
  CarmenLaser l = type == CarmenLaserType::kRobotLaser1 ? parseRobotLaser(tok, where)
                  : type == CarmenLaserType::kFlaser || type == CarmenLaserType::kRlaser
                      ? parseFlaser(tok, where)
                      : parseRawLaser(tok, where);
  tok.finish();
  l.type = type;
  l.line = where.line;
  return l;
}

/// The latest stamp of a stream so far; checks each new line against it.
struct StreamOrder {
  double max_stamp_s = -std::numeric_limits<double>::infinity();
  std::size_t max_line = 0;
  std::string_view max_text;  ///< that line, to recognise a message logged twice
  bool out_of_order = false;
  std::size_t repeats = 0;

  /// False for a line identical to the latest one (dropped and counted); throws for a stamp
  /// beyond the tolerance or (unless p.drop_late) equal to the latest.
  bool check(double stamp_s, std::string_view text, const TextLocation& where,
             std::string_view stream, const CarmenReadParams& p) {
    if (stamp_s > max_stamp_s) {
      max_stamp_s = stamp_s;
      max_line = where.line;
      max_text = text;
      return true;
    }
    if (stamp_s == max_stamp_s && text == max_text) {
      ++repeats;
      return false;
    }
    std::string stamp, latest;
    appendDouble(stamp, stamp_s);
    appendDouble(latest, max_stamp_s);
    const std::string earlier = " on line " + std::to_string(max_line);
    // Dropping late lines removes the earlier of two equal stamps; sorting cannot order them.
    if (stamp_s == max_stamp_s && !p.drop_late)
      throw InputError(where.str(),
                       "timestamp: duplicate timestamp " + stamp + " (also" + earlier + ")");
    const double back_s = max_stamp_s - stamp_s;
    if (!(back_s <= p.reorder_tolerance_s))
      throw InputError(where.str(),
                       "timestamp: " + stamp + " is " + std::to_string(back_s) + " s before " +
                           latest + earlier + " (" + std::string(stream) +
                           "): out of order by more than the reorder tolerance " +
                           std::to_string(p.reorder_tolerance_s) + " s (--reorder-tolerance)");
    out_of_order = true;
    return true;
  }
};

/// Puts a stream whose stamps ran backwards in order: sorts it stably by stamp (refusing equal
/// stamps), or with drop_late drops every line stamped at or after a later line of the stream.
/// Returns how many lines were moved or dropped.
template <typename T, typename Stamp>
std::size_t restoreOrder(std::vector<T>& lines, const StreamOrder& order, bool drop_late,
                         const std::string& file, Stamp stamp) {
  if (!order.out_of_order) return 0;
  const std::size_t n = lines.size();
  if (drop_late) {
    std::vector<bool> late(n, false);
    double later_min = std::numeric_limits<double>::infinity();
    for (std::size_t i = n; i-- > 0;) {
      late[i] = stamp(lines[i]) >= later_min;
      later_min = std::min(later_min, stamp(lines[i]));
    }
    std::vector<T> kept;
    for (std::size_t i = 0; i < n; ++i)
      if (!late[i]) kept.push_back(std::move(lines[i]));
    lines = std::move(kept);
    return n - lines.size();
  }
  std::vector<double> before;
  for (const T& l : lines) before.push_back(stamp(l));
  std::stable_sort(lines.begin(), lines.end(),
                   [&](const T& a, const T& b) { return stamp(a) < stamp(b); });
  std::size_t moved = 0;
  for (std::size_t i = 0; i < n; ++i) moved += stamp(lines[i]) != before[i];
  for (std::size_t i = 1; i < n; ++i)
    if (stamp(lines[i]) == stamp(lines[i - 1])) {
      std::string what = "timestamp: duplicate timestamp ";
      appendDouble(what, stamp(lines[i]));
      throw InputError(TextLocation{file, std::max(lines[i].line, lines[i - 1].line)}.str(),
                       what + " (also on line " +
                           std::to_string(std::min(lines[i].line, lines[i - 1].line)) + ")");
    }
  return moved;
}

}  // namespace

std::string_view carmenMessageName(CarmenLaserType type) {
  return nameOf(kLaserNames, type);
}

std::optional<CarmenLaserType> parseCarmenLaserType(std::string_view name) {
  return findName(kLaserNames, name);
}

CarmenLog parseCarmen(std::string_view text, const std::string& file,
                      const CarmenReadParams& params) {
  CarmenLog log;
  LineCursor cursor(text);
  std::string_view line;
  std::vector<std::string_view> fields;
  TextLocation where{file, 0};
  StreamOrder odom_order;
  std::map<CarmenLaserType, StreamOrder> laser_order;
  while (cursor.next(line)) {
    where.line = cursor.lineNumber();
    splitWhitespace(line, fields);
    if (fields.empty()) continue;
    if (fields[0].starts_with('#')) {
      ++log.comment_lines;
      continue;
    }
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
      if (odom_order.check(o.stamp_s, trim(line), where, "ODOM", params)) log.odometry.push_back(o);
    } else if (const auto type = parseCarmenLaserType(fields[0])) {
      CarmenLaser l = parseLaser(*type, tok, where);
      if (laser_order[*type].check(l.scan.stamp_s, trim(line), where, fields[0], params))
        log.lasers[*type].push_back(std::move(l));
    } else if (fields[0] == "PARAM" && fields.size() >= 3) {
      log.params[std::string(fields[1])] = {std::string(fields[2]), where.line};
    } else {
      ++log.skipped[std::string(fields[0])];
    }
  }
  const auto note = [&](const std::string& stream, const StreamOrder& order, std::size_t n) {
    if (n) log.out_of_order[stream] = n;
    if (order.repeats) log.repeated[stream] = order.repeats;
  };
  note("ODOM", odom_order,
       restoreOrder(log.odometry, odom_order, params.drop_late, file,
                    [](const CarmenOdom& o) { return o.stamp_s; }));
  for (auto& [type, order] : laser_order)
    note(std::string(carmenMessageName(type)), order,
         restoreOrder(log.lasers[type], order, params.drop_late, file,
                      [](const CarmenLaser& l) { return l.scan.stamp_s; }));
  return log;
}

}  // namespace slamprep::eval
