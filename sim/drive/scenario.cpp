#include "sim/drive/scenario.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <numbers>
#include <set>
#include <sstream>

#include "core/error.hpp"
#include "sim/drive/rng.hpp"
#include "sim/yaml/yaml_fields.hpp"

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

namespace {

constexpr double kDegToRad = std::numbers::pi / 180.0;
constexpr int kMaxIncludeDepth = 16;

// ---- Reading fields (sim/yaml: every error names file, line, column and key) -----------------

/// A scenario file being read: messages name `doc.file()`, includes resolve next to `path`.
struct Context {
  YamlDoc doc;
  std::filesystem::path path;
};

// Bounds no real drive reaches; they keep every derived time and knot count finite and small.
constexpr double kMaxDuration_s = 86400.0;  ///< the simulator runs at most one day (config.cpp)
constexpr double kMaxValue = 1e6;           ///< any other positive field (m, m/s, rad/s, m/s^2)
constexpr int kMaxCount = 10000;            ///< laps, loops, repeats
constexpr double kMaxKnots = 1e6;           ///< random_smooth: duration_s / interval_s

/// map[name] as a number; `fallback` when absent, required when fallback is NaN.
double field(const Context& ctx, const YAML::Node& map, const std::string& prefix,
             const std::string& name, double fallback, const Bounds& bounds = {}) {
  if (!map[name] && std::isnan(fallback)) ctx.doc.required(map, name, prefix);
  return ctx.doc.optionalNumber(map, name, prefix, fallback, bounds);
}

double positiveField(const Context& ctx, const YAML::Node& map, const std::string& prefix,
                     const std::string& name, double fallback) {
  // A longer segment than the simulator can run is a typo, not a plan.
  const double max = name == "duration_s" ? kMaxDuration_s : kMaxValue;
  return field(ctx, map, prefix, name, fallback, Bounds{0.0, max, true});
}

double nonZeroField(const Context& ctx, const YAML::Node& map, const std::string& prefix,
                    const std::string& name) {
  const double value = field(ctx, map, prefix, name, std::nan(""), Bounds{-kMaxValue, kMaxValue});
  if (value == 0.0) ctx.doc.fail(map[name], joinKey(prefix, name), "must not be zero");
  return value;
}

int countField(const Context& ctx, const YAML::Node& map, const std::string& prefix,
               const std::string& name, int fallback) {
  const YAML::Node node = map[name];
  return node ? static_cast<int>(ctx.doc.integer(node, joinKey(prefix, name), 1, kMaxCount))
              : fallback;
}

std::string stringField(const Context& ctx, const YAML::Node& map, const std::string& prefix,
                        const std::string& name) {
  return ctx.doc.string(ctx.doc.required(map, name, prefix), joinKey(prefix, name));
}

// ---- Segment shapes ------------------------------------------------------------------------

/// Rest-to-rest trapezoid s(t) * peak: s ramps 0 -> 1 in ramp_s, holds, ramps back; its area
/// (integral of s) is area_s. When area_s < ramp_s the peak is lowered to a triangle:
/// p = sqrt(area / ramp), rise time p * ramp, area p^2 * ramp = area.
std::vector<CommandKnot> trapezoid(const Eigen::Vector2d& peak, double ramp_s, double area_s) {
  assert(ramp_s > 0.0 && area_s > 0.0);
  const double p = area_s >= ramp_s ? 1.0 : std::sqrt(area_s / ramp_s);
  const double rise_s = p * ramp_s;
  const double hold_s = area_s / p - rise_s;  // area = p * (rise + hold)
  std::vector<CommandKnot> knots{{0.0, Eigen::Vector2d::Zero()}, {rise_s, p * peak}};
  if (hold_s > 1e-12) knots.push_back({rise_s + hold_s, p * peak});
  knots.push_back({knots.back().t_s + rise_s, Eigen::Vector2d::Zero()});
  return knots;
}

/// Ramp time of a twist command from rest under the limits (both components ramp together).
double twistRamp(const Eigen::Vector2d& twist, const AccelerationLimits& limits) {
  return std::max(std::abs(twist.x()) / limits.linear_mps2,
                  std::abs(twist.y()) / limits.angular_radps2);
}

struct SegmentBuilder {
  const Context& ctx;
  const AccelerationLimits& limits;
  std::vector<ProfileSegment>& out;

  void add(const std::string& type, const std::string& at, CommandKind kind,
           std::vector<CommandKnot> knots) {
    out.push_back({type, at, kind, std::move(knots)});
  }
  void twist(const std::string& type, const std::string& at, const Eigen::Vector2d& peak,
             double area_s) {
    add(type, at, CommandKind::twist, trapezoid(peak, twistRamp(peak, limits), area_s));
  }
  void straight(const std::string& type, const std::string& at, double distance_m,
                double speed_mps) {
    twist(type, at, {std::copysign(speed_mps, distance_m), 0.0}, std::abs(distance_m) / speed_mps);
  }
  void spin(const std::string& type, const std::string& at, double angle_rad, double rate_radps) {
    twist(type, at, {0.0, std::copysign(rate_radps, angle_rad)}, std::abs(angle_rad) / rate_radps);
  }
  void stop(const std::string& type, const std::string& at, double duration_s) {
    add(type, at, CommandKind::twist, {{0.0, {0, 0}}, {duration_s, {0, 0}}});
  }
};

/// Figure eight: `loops` times a full left circle then a full right circle of radius R at speed V.
/// Both components ramp together at the start and end (constant curvature, so the ramps stay on
/// the circle); the w flips between circles are linear ramps centred on the ideal switching time,
/// which keeps the heading integral of every circle exactly 2 pi.
std::vector<CommandKnot> figureEight(double radius_m, double speed_mps, int loops,
                                     const AccelerationLimits& limits, const std::string& at) {
  const double w = speed_mps / radius_m;
  const double ramp_s = twistRamp({speed_mps, w}, limits);
  const double flip_s = 2.0 * w / limits.angular_radps2;
  const double circle_s = 2.0 * std::numbers::pi / w;  // one full turn at w
  if (circle_s < flip_s || circle_s < 0.5 * (ramp_s + flip_s)) {
    throw InputError(at,
                     "circles too short for the acceleration limits (lower speed_mps or raise "
                     "radius_m)");
  }
  std::vector<CommandKnot> knots{{0.0, {0, 0}}, {ramp_s, {speed_mps, w}}};
  double t_switch = circle_s + 0.5 * ramp_s;  // heading of the first circle reaches 2 pi
  double sign = 1.0;
  for (int c = 1; c < 2 * loops; ++c) {
    knots.push_back({t_switch - 0.5 * flip_s, {speed_mps, sign * w}});
    knots.push_back({t_switch + 0.5 * flip_s, {speed_mps, -sign * w}});
    sign = -sign;
    t_switch += circle_s;
  }
  const double end_s = t_switch + 0.5 * ramp_s;  // t_switch: ideal end of the last circle
  knots.push_back({end_s - ramp_s, {speed_mps, sign * w}});
  knots.push_back({end_s, {0, 0}});
  return knots;
}

/// Random smooth twist: knots every interval_s with uniform random targets, each change limited
/// by the acceleration limits, and an envelope that brings the command back to rest at the end.
std::vector<CommandKnot> randomSmooth(double duration_s, double interval_s, double min_speed_mps,
                                      double max_speed_mps, double max_turn_radps,
                                      std::uint64_t seed, const AccelerationLimits& limits) {
  const int n = std::max(2, static_cast<int>(std::lround(duration_s / interval_s)));
  const double dv = limits.linear_mps2 * interval_s;
  const double dw = limits.angular_radps2 * interval_s;
  SplitMix64 rng(seed);
  std::vector<CommandKnot> knots{{0.0, {0, 0}}};
  Eigen::Vector2d prev = Eigen::Vector2d::Zero();
  for (int k = 1; k <= n; ++k) {
    const int steps_left = std::min(k, n - k);  // reachable from rest and back to rest
    const double v_target = min_speed_mps + (max_speed_mps - min_speed_mps) * rng.uniform();
    const double w_target = max_turn_radps * (2.0 * rng.uniform() - 1.0);
    // Clamp to the reachable band first, then to the envelope (the intersection is non-empty).
    double v = std::clamp(v_target, prev.x() - dv, prev.x() + dv);
    double w = std::clamp(w_target, prev.y() - dw, prev.y() + dw);
    v = std::clamp(v, -steps_left * dv, steps_left * dv);
    w = std::clamp(w, -steps_left * dw, steps_left * dw);
    prev = {v, w};
    knots.push_back({k * interval_s, prev});
  }
  knots.back().value.setZero();
  return knots;
}

// ---- The file ------------------------------------------------------------------------------

CommandProfile loadProfile(const std::filesystem::path& file, std::vector<std::string>& stack,
                           Scenario* top);

AccelerationLimits parseLimits(const Context& ctx, const YAML::Node& node) {
  AccelerationLimits limits;
  if (!node) return limits;
  ctx.doc.requireMap(node, "limits");
  ctx.doc.checkKeys(node, "limits",
                    {"linear_accel_mps2", "angular_accel_radps2", "wheel_accel_radps2"});
  limits.linear_mps2 = positiveField(ctx, node, "limits", "linear_accel_mps2", limits.linear_mps2);
  limits.angular_radps2 =
      positiveField(ctx, node, "limits", "angular_accel_radps2", limits.angular_radps2);
  limits.wheel_radps2 =
      positiveField(ctx, node, "limits", "wheel_accel_radps2", limits.wheel_radps2);
  return limits;
}

void parseSegment(const Context& ctx, const YAML::Node& seg, const std::string& key,
                  const AccelerationLimits& limits, std::vector<std::string>& stack,
                  CommandProfile& profile) {
  ctx.doc.requireMap(seg, key);
  const std::string& p = key;
  const std::string type = stringField(ctx, seg, p, "type");
  const std::string at = ctx.doc.whereLine(seg, key) + " (" + type + ")";
  std::vector<ProfileSegment> out;
  SegmentBuilder build{ctx, limits, out};
  auto keys = [&](std::set<std::string> allowed) {
    allowed.insert("type");
    ctx.doc.checkKeys(seg, p, allowed);
  };
  if (type == "straight") {
    keys({"distance_m", "speed_mps"});
    build.straight(type, at, nonZeroField(ctx, seg, p, "distance_m"),
                   positiveField(ctx, seg, p, "speed_mps", 0.5));
  } else if (type == "spin") {
    keys({"angle_deg", "rate_radps"});
    build.spin(type, at, nonZeroField(ctx, seg, p, "angle_deg") * kDegToRad,
               positiveField(ctx, seg, p, "rate_radps", 1.0));
  } else if (type == "arc") {
    keys({"v_mps", "w_radps", "duration_s", "angle_deg"});
    const Bounds signed_value{-kMaxValue, kMaxValue};
    const Eigen::Vector2d twist(field(ctx, seg, p, "v_mps", std::nan(""), signed_value),
                                field(ctx, seg, p, "w_radps", std::nan(""), signed_value));
    if (twist.isZero()) throw InputError(at, "v_mps and w_radps are both zero");
    if (seg["duration_s"].IsDefined() == seg["angle_deg"].IsDefined()) {
      throw InputError(at, "give exactly one of duration_s and angle_deg");
    }
    double area_s = 0.0;
    if (seg["duration_s"]) {
      area_s = positiveField(ctx, seg, p, "duration_s", 0.0);
    } else {
      if (twist.y() == 0.0) throw InputError(at, "angle_deg needs a non-zero w_radps");
      area_s = std::abs(nonZeroField(ctx, seg, p, "angle_deg") * kDegToRad / twist.y());
    }
    build.twist(type, at, twist, area_s);
  } else if (type == "wheel_rates") {
    keys({"left_radps", "right_radps", "duration_s"});
    const Bounds signed_value{-kMaxValue, kMaxValue};
    const Eigen::Vector2d rates(field(ctx, seg, p, "left_radps", std::nan(""), signed_value),
                                field(ctx, seg, p, "right_radps", std::nan(""), signed_value));
    if (rates.isZero()) throw InputError(at, "left_radps and right_radps are both zero");
    const double ramp_s = rates.cwiseAbs().maxCoeff() / limits.wheel_radps2;
    build.add(type, at, CommandKind::wheel_rates,
              trapezoid(rates, ramp_s, positiveField(ctx, seg, p, "duration_s", std::nan(""))));
  } else if (type == "stop") {
    keys({"duration_s"});
    build.stop(type, at, positiveField(ctx, seg, p, "duration_s", std::nan("")));
  } else if (type == "umbmark") {
    keys({"direction", "side_m", "speed_mps", "turn_rate_radps", "pause_s", "laps"});
    const std::string direction = stringField(ctx, seg, p, "direction");
    if (direction != "cw" && direction != "ccw")
      ctx.doc.fail(seg["direction"], joinKey(p, "direction"), "expected cw or ccw");
    const double side_m = positiveField(ctx, seg, p, "side_m", 3.0);
    const double speed = positiveField(ctx, seg, p, "speed_mps", 0.5);
    const double turn = positiveField(ctx, seg, p, "turn_rate_radps", 0.5);
    const double pause_s = positiveField(ctx, seg, p, "pause_s", 0.5);
    const int laps = countField(ctx, seg, p, "laps", 1);
    const double angle = (direction == "ccw" ? 1.0 : -1.0) * std::numbers::pi / 2.0;
    for (int leg = 0; leg < 4 * laps; ++leg) {
      build.straight(type, at, side_m, speed);
      build.stop(type, at, pause_s);
      build.spin(type, at, angle, turn);
      build.stop(type, at, pause_s);
    }
  } else if (type == "figure_eight") {
    keys({"radius_m", "speed_mps", "loops"});
    build.add(type, at, CommandKind::twist,
              figureEight(positiveField(ctx, seg, p, "radius_m", 1.0),
                          positiveField(ctx, seg, p, "speed_mps", 0.5),
                          countField(ctx, seg, p, "loops", 1), limits, at));
  } else if (type == "stop_and_go") {
    keys({"distance_m", "speed_mps", "stop_s", "repeats"});
    const double distance_m = nonZeroField(ctx, seg, p, "distance_m");
    const double speed = positiveField(ctx, seg, p, "speed_mps", 0.5);
    const double stop_s = positiveField(ctx, seg, p, "stop_s", 1.0);
    const int repeats = countField(ctx, seg, p, "repeats", 3);
    for (int k = 0; k < repeats; ++k) {
      build.straight(type, at, distance_m, speed);
      build.stop(type, at, stop_s);
    }
  } else if (type == "random_smooth") {
    keys({"duration_s", "interval_s", "min_speed_mps", "max_speed_mps", "max_turn_rate_radps",
          "seed"});
    const double duration_s = positiveField(ctx, seg, p, "duration_s", std::nan(""));
    const double interval_s = positiveField(ctx, seg, p, "interval_s", 1.0);
    if (duration_s / interval_s > kMaxKnots)
      ctx.doc.fail(seg["interval_s"], joinKey(p, "interval_s"),
                   "too small for duration_s: more than 1e6 knots");
    const Bounds speed{-kMaxValue, kMaxValue};
    const double min_v = field(ctx, seg, p, "min_speed_mps", 0.0, speed);
    const double max_v = field(ctx, seg, p, "max_speed_mps", 0.5, speed);
    if (max_v < min_v) throw InputError(at, "max_speed_mps is below min_speed_mps");
    const double max_w = field(ctx, seg, p, "max_turn_rate_radps", 1.0, Bounds{0.0, kMaxValue});
    const YAML::Node seed = seg["seed"];
    const std::int64_t seed_value =
        seed ? ctx.doc.integer(seed, joinKey(p, "seed"), 0, std::int64_t{1} << 53) : 1;
    build.add(type, at, CommandKind::twist,
              randomSmooth(duration_s, interval_s, min_v, max_v, max_w,
                           static_cast<std::uint64_t>(seed_value), limits));
  } else if (type == "include") {
    keys({"file"});
    std::filesystem::path file = stringField(ctx, seg, p, "file");
    if (file.is_relative()) file = ctx.path.parent_path() / file;
    profile.append(loadProfile(file, stack, nullptr));
    return;
  } else {
    ctx.doc.fail(seg["type"], joinKey(p, "type"),
                 "unknown segment type '" + type +
                     "' (expected straight, spin, arc, wheel_rates, stop, umbmark, "
                     "figure_eight, stop_and_go, random_smooth or include)");
  }
  for (ProfileSegment& segment : out) profile.append(std::move(segment));
}

CommandProfile readProfile(const Context& ctx, const YAML::Node& root,
                           std::vector<std::string>& stack, Scenario* top) {
  if (!root.IsMap()) throw InputError(ctx.doc.file(), "expected a mapping with a 'segments' list");
  ctx.doc.checkKeys(root, "", {"name", "description", "limits", "segments"});
  const AccelerationLimits limits = parseLimits(ctx, root["limits"]);
  const YAML::Node segments = root["segments"];
  if (!segments) throw InputError(ctx.doc.file() + ": segments", "missing");
  if (!segments.IsSequence() || segments.size() == 0)
    ctx.doc.fail(segments, "segments", "expected a non-empty list");
  CommandProfile profile;
  for (std::size_t k = 0; k < segments.size(); ++k) {
    const std::string key = "segments[" + std::to_string(k) + "]";
    parseSegment(ctx, segments[k], key, limits, stack, profile);
    // Checked as segments are added, so a huge count of long segments stops at the first day.
    if (profile.duration_s() > kMaxDuration_s)
      ctx.doc.fail(segments[k], key,
                   "the scenario lasts more than one day (86400 s) by the end of this segment");
  }
  if (top != nullptr) {
    top->limits = limits;
    const YAML::Node name = root["name"];
    top->name = name ? ctx.doc.string(name, "name") : ctx.path.stem().string();
  }
  return profile;
}

CommandProfile parseProfile(const std::string& text, const Context& ctx,
                            std::vector<std::string>& stack, Scenario* top) {
  const YAML::Node root = parseYaml(text, ctx.doc);
  return ctx.doc.guard([&] { return readProfile(ctx, root, stack, top); });
}

std::string readText(const std::filesystem::path& file, const std::string& where_s) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(where_s, "cannot open scenario file '" + file.string() + "'");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

CommandProfile loadProfile(const std::filesystem::path& file, std::vector<std::string>& stack,
                           Scenario* top) {
  const std::string where_s = stack.empty() ? file.string() : stack.back();
  const std::string text = readText(file, where_s);
  const std::string id = std::filesystem::weakly_canonical(file).string();
  if (std::find(stack.begin(), stack.end(), id) != stack.end() ||
      static_cast<int>(stack.size()) >= kMaxIncludeDepth) {
    throw InputError(file.string(), "include cycle (or nesting deeper than 16)");
  }
  stack.push_back(id);
  CommandProfile profile = parseProfile(text, {YamlDoc(file.string()), file}, stack, top);
  stack.pop_back();
  return profile;
}

}  // namespace

Scenario loadScenario(const std::filesystem::path& file) {
  Scenario scenario;
  scenario.source = file;
  std::vector<std::string> stack;
  scenario.profile = loadProfile(file, stack, &scenario);
  return scenario;
}

Scenario parseScenario(const std::string& yaml_text, const std::filesystem::path& source) {
  Scenario scenario;
  scenario.source = source;
  std::vector<std::string> stack{std::filesystem::weakly_canonical(source).string()};
  scenario.profile = parseProfile(yaml_text, {YamlDoc(source.string()), source}, stack, &scenario);
  return scenario;
}

}  // namespace slamprep::sim
