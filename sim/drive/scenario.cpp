#include "slamprep/sim/drive/scenario.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <optional>
#include <set>
#include <utility>

#include "slamprep/core/error.hpp"
#include "slamprep/core/input_file.hpp"
#include "slamprep/sim/drive/explore.hpp"
#include "slamprep/sim/drive/segment_shapes.hpp"
#include "slamprep/sim/yaml/yaml_fields.hpp"

namespace slamprep::sim {
namespace {

constexpr double kDegToRad = std::numbers::pi / 180.0;
constexpr int kMaxIncludeDepth = 16;
// Files read for one scenario, includes of includes counted each time: a chain of files that
// each include the next twice would otherwise read 2^16 files.
constexpr int kMaxIncludedFiles = 256;

/// The include chain being read (canonical paths, outermost first) and the files read so far.
struct IncludeStack {
  std::vector<std::string> files;
  int loaded = 0;
  std::vector<std::filesystem::path> read;  ///< every file read, once (an output must spare them)
};

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

// ---- Segments ------------------------------------------------------------------------------

/// Expands one entry of `segments` into rest-to-rest pieces under the limits.
struct SegmentBuilder {
  const Context& ctx;
  const AccelerationLimits& limits;
  std::vector<ProfileSegment>& out;

  void add(const std::string& type, const std::string& at, CommandKind kind,
           std::vector<CommandKnot> knots) {
    out.push_back({type, at, kind, std::move(knots), nullptr, std::nullopt});
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

/// arc: a constant twist for duration_s, or until the heading has turned by angle_deg.
void parseArc(const YAML::Node& seg, const std::string& p, const std::string& type,
              const std::string& at, SegmentBuilder& build) {
  const Context& ctx = build.ctx;
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
}

/// wheel_rates: constant wheel rates for duration_s, ramped under the wheel limit.
void parseWheelRates(const YAML::Node& seg, const std::string& p, const std::string& type,
                     const std::string& at, SegmentBuilder& build) {
  const Context& ctx = build.ctx;
  const AccelerationLimits& limits = build.limits;
  const Bounds signed_value{-kMaxValue, kMaxValue};
  const Eigen::Vector2d rates(field(ctx, seg, p, "left_radps", std::nan(""), signed_value),
                              field(ctx, seg, p, "right_radps", std::nan(""), signed_value));
  if (rates.isZero()) throw InputError(at, "left_radps and right_radps are both zero");
  const double ramp_s = rates.cwiseAbs().maxCoeff() / limits.wheel_radps2;
  build.add(type, at, CommandKind::wheel_rates,
            trapezoid(rates, ramp_s, positiveField(ctx, seg, p, "duration_s", std::nan(""))));
}

/// umbmark: the UMBmark square, `laps` times round, with a pause after every side and turn.
void parseUmbmark(const YAML::Node& seg, const std::string& p, const std::string& type,
                  const std::string& at, SegmentBuilder& build) {
  const Context& ctx = build.ctx;
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
}

/// stop_and_go: `repeats` times a straight followed by a stop.
void parseStopAndGo(const YAML::Node& seg, const std::string& p, const std::string& type,
                    const std::string& at, SegmentBuilder& build) {
  const Context& ctx = build.ctx;
  const double distance_m = nonZeroField(ctx, seg, p, "distance_m");
  const double speed = positiveField(ctx, seg, p, "speed_mps", 0.5);
  const double stop_s = positiveField(ctx, seg, p, "stop_s", 1.0);
  const int repeats = countField(ctx, seg, p, "repeats", 3);
  for (int k = 0; k < repeats; ++k) {
    build.straight(type, at, distance_m, speed);
    build.stop(type, at, stop_s);
  }
}

/// random_smooth: a seeded random smooth twist (segment_shapes.hpp).
void parseRandomSmooth(const YAML::Node& seg, const std::string& p, const std::string& type,
                       const std::string& at, SegmentBuilder& build) {
  const Context& ctx = build.ctx;
  const AccelerationLimits& limits = build.limits;
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
}

/// explore: random goals in the world's free space, planned when the simulator knows the world
/// (sim/drive/explore.hpp); until then a stop of the same length.
void parseExplore(const YAML::Node& seg, const std::string& p, const std::string& type,
                  const std::string& at, SegmentBuilder& build) {
  const Context& ctx = build.ctx;
  auto params = std::make_shared<ExploreParams>();
  ExploreParams& e = *params;
  e.duration_s = positiveField(ctx, seg, p, "duration_s", std::nan(""));
  e.min_speed_mps = positiveField(ctx, seg, p, "min_speed_mps", e.min_speed_mps);
  e.max_speed_mps = positiveField(ctx, seg, p, "max_speed_mps", e.max_speed_mps);
  if (e.max_speed_mps < e.min_speed_mps)
    throw InputError(at, "max_speed_mps is below min_speed_mps");
  e.max_turn_rate_radps = positiveField(ctx, seg, p, "max_turn_rate_radps", e.max_turn_rate_radps);
  e.clearance_m = field(ctx, seg, p, "clearance_m", e.clearance_m, Bounds{0.0, kMaxValue});
  e.lookahead_m = positiveField(ctx, seg, p, "lookahead_m", e.lookahead_m);
  e.min_goal_distance_m =
      field(ctx, seg, p, "min_goal_distance_m", e.min_goal_distance_m, Bounds{0.0, kMaxValue});
  e.grid_resolution_m =
      field(ctx, seg, p, "grid_resolution_m", e.grid_resolution_m, Bounds{0.01, 1.0});
  e.control_period_s =
      field(ctx, seg, p, "control_period_s", e.control_period_s, Bounds{0.01, 1.0});
  if (e.duration_s / e.control_period_s > kMaxKnots)
    ctx.doc.fail(seg["control_period_s"], joinKey(p, "control_period_s"),
                 "too small for duration_s: more than 1e6 knots");
  const YAML::Node seed = seg["seed"];
  e.seed = seed ? static_cast<std::uint64_t>(
                      ctx.doc.integer(seed, joinKey(p, "seed"), 0, std::int64_t{1} << 53))
                : 1;
  e.limits = build.limits;
  build.stop(type, at, e.duration_s);
  build.out.back().explore = std::move(params);
}

/// A track's closed loop (tracking_law.hpp): `closed_loop: true` and its optional gains and cap;
/// none when closed_loop is absent or false (the gains are then refused: they would do nothing).
std::optional<TrackingParams> parseClosedLoop(const Context& ctx, const YAML::Node& seg,
                                              const std::string& p) {
  const YAML::Node on = seg["closed_loop"];
  const bool closed = on && ctx.doc.boolean(on, joinKey(p, "closed_loop"));
  TrackingParams t;
  const Bounds gain{0.0, kMaxValue};
  for (const char* name : {"k_x_per_s", "k_y_per_m2", "k_theta_per_m", "max_wheel_radps"})
    if (seg[name] && !closed)
      ctx.doc.fail(seg[name], joinKey(p, name), "only with closed_loop: true");
  if (!closed) return std::nullopt;
  t.k_x_per_s = field(ctx, seg, p, "k_x_per_s", t.k_x_per_s, gain);
  t.k_y_per_m2 = field(ctx, seg, p, "k_y_per_m2", t.k_y_per_m2, gain);
  t.k_theta_per_m = field(ctx, seg, p, "k_theta_per_m", t.k_theta_per_m, gain);
  if (seg["max_wheel_radps"])
    t.max_wheel_radps = positiveField(ctx, seg, p, "max_wheel_radps", t.max_wheel_radps);
  return t;
}

/// track: knots every period_s, linear between them, as a tool writes a recorded drive
/// (slamprep twin); a zero knot before the first value and after the last keep it rest to rest.
void parseTrack(const YAML::Node& seg, const std::string& p, const std::string& type,
                const std::string& at, SegmentBuilder& build) {
  const Context& ctx = build.ctx;
  const std::string kind_name = stringField(ctx, seg, p, "kind");
  const auto kind = findName(kCommandKindNames, kind_name);
  if (!kind)
    ctx.doc.fail(seg["kind"], joinKey(p, "kind"),
                 unknownNameMessage("kind", kind_name, namesOf(kCommandKindNames)));
  const double period_s = positiveField(ctx, seg, p, "period_s", std::nan(""));
  const YAML::Node values = ctx.doc.required(seg, "values", p);
  const std::string key = joinKey(p, "values");
  if (!values.IsSequence() || values.size() == 0)
    ctx.doc.fail(values, key, "must be a non-empty list of [a, b] pairs");
  if (double(values.size() + 1) * period_s > kMaxDuration_s || double(values.size()) > kMaxKnots)
    ctx.doc.fail(values, key, "longer than a day or more than 1e6 knots");
  std::vector<CommandKnot> knots{{0.0, {0.0, 0.0}}};
  const Bounds signed_value{-kMaxValue, kMaxValue};
  for (std::size_t k = 0; k < values.size(); ++k)
    knots.push_back({double(k + 1) * period_s,
                     ctx.doc.point(values[k], key + "[" + std::to_string(k) + "]", signed_value)});
  knots.push_back({double(values.size() + 1) * period_s, {0.0, 0.0}});
  build.add(type, at, *kind, std::move(knots));
  build.out.back().closed_loop = parseClosedLoop(ctx, seg, p);
}

// ---- The file ------------------------------------------------------------------------------

CommandProfile loadProfile(const std::filesystem::path& file, IncludeStack& stack, Scenario* top);

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

void parseStraight(const YAML::Node& seg, const std::string& p, const std::string& type,
                   const std::string& at, SegmentBuilder& build) {
  const Context& ctx = build.ctx;
  build.straight(type, at, nonZeroField(ctx, seg, p, "distance_m"),
                 positiveField(ctx, seg, p, "speed_mps", 0.5));
}

void parseSpin(const YAML::Node& seg, const std::string& p, const std::string& type,
               const std::string& at, SegmentBuilder& build) {
  const Context& ctx = build.ctx;
  build.spin(type, at, nonZeroField(ctx, seg, p, "angle_deg") * kDegToRad,
             positiveField(ctx, seg, p, "rate_radps", 1.0));
}

void parseStop(const YAML::Node& seg, const std::string& p, const std::string& type,
               const std::string& at, SegmentBuilder& build) {
  build.stop(type, at, positiveField(build.ctx, seg, p, "duration_s", std::nan("")));
}

void parseFigureEight(const YAML::Node& seg, const std::string& p, const std::string& type,
                      const std::string& at, SegmentBuilder& build) {
  const Context& ctx = build.ctx;
  build.add(type, at, CommandKind::twist,
            figureEight(positiveField(ctx, seg, p, "radius_m", 1.0),
                        positiveField(ctx, seg, p, "speed_mps", 0.5),
                        countField(ctx, seg, p, "loops", 1), build.limits, at));
}

using SegmentParser = void (*)(const YAML::Node& seg, const std::string& p, const std::string& type,
                               const std::string& at, SegmentBuilder& build);

/// A segment type: the keys it allows besides "type", and what expands it.
struct SegmentType {
  const char* name;
  std::set<std::string> keys;
  SegmentParser parse;
};

/// Every segment type but include (which reads a file, not knots), in the order of the
/// unknown-type message.
const std::vector<SegmentType>& segmentTypes() {
  static const std::vector<SegmentType> types{
      {"straight", {"distance_m", "speed_mps"}, parseStraight},
      {"spin", {"angle_deg", "rate_radps"}, parseSpin},
      {"arc", {"v_mps", "w_radps", "duration_s", "angle_deg"}, parseArc},
      {"wheel_rates", {"left_radps", "right_radps", "duration_s"}, parseWheelRates},
      {"stop", {"duration_s"}, parseStop},
      {"umbmark",
       {"direction", "side_m", "speed_mps", "turn_rate_radps", "pause_s", "laps"},
       parseUmbmark},
      {"figure_eight", {"radius_m", "speed_mps", "loops"}, parseFigureEight},
      {"stop_and_go", {"distance_m", "speed_mps", "stop_s", "repeats"}, parseStopAndGo},
      {"random_smooth",
       {"duration_s", "interval_s", "min_speed_mps", "max_speed_mps", "max_turn_rate_radps",
        "seed"},
       parseRandomSmooth},
      {"explore",
       {"duration_s", "seed", "min_speed_mps", "max_speed_mps", "max_turn_rate_radps",
        "clearance_m", "lookahead_m", "min_goal_distance_m", "grid_resolution_m",
        "control_period_s"},
       parseExplore},
      {"track",
       {"kind", "period_s", "values", "closed_loop", "k_x_per_s", "k_y_per_m2", "k_theta_per_m",
        "max_wheel_radps"},
       parseTrack},
  };
  return types;
}

void parseSegment(const Context& ctx, const YAML::Node& seg, const std::string& key,
                  const AccelerationLimits& limits, IncludeStack& stack, CommandProfile& profile) {
  ctx.doc.requireMap(seg, key);
  const std::string& p = key;
  const std::string type = stringField(ctx, seg, p, "type");
  const std::string at = ctx.doc.whereLine(seg, key) + " (" + type + ")";
  auto keys = [&](std::set<std::string> allowed) {
    allowed.insert("type");
    ctx.doc.checkKeys(seg, p, allowed);
  };
  if (type == "include") {
    keys({"file"});
    std::filesystem::path file = stringField(ctx, seg, p, "file");
    if (file.is_relative()) file = ctx.path.parent_path() / file;
    profile.append(loadProfile(file, stack, nullptr));
    return;
  }
  const auto& types = segmentTypes();
  const auto it = std::find_if(types.begin(), types.end(),
                               [&](const SegmentType& t) { return type == t.name; });
  if (it == types.end())
    ctx.doc.fail(seg["type"], joinKey(p, "type"),
                 "unknown segment type '" + type +
                     "' (expected straight, spin, arc, wheel_rates, stop, umbmark, "
                     "figure_eight, stop_and_go, random_smooth, explore, track or include)");
  keys(it->keys);
  std::vector<ProfileSegment> out;
  SegmentBuilder build{ctx, limits, out};
  it->parse(seg, p, type, at, build);
  for (ProfileSegment& segment : out) profile.append(std::move(segment));
}

CommandProfile readProfile(const Context& ctx, const YAML::Node& root, IncludeStack& stack,
                           Scenario* top) {
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

CommandProfile parseProfile(const std::string& text, const Context& ctx, IncludeStack& stack,
                            Scenario* top) {
  const YAML::Node root = parseYaml(text, ctx.doc);
  return ctx.doc.guard([&] { return readProfile(ctx, root, stack, top); });
}

CommandProfile loadProfile(const std::filesystem::path& file, IncludeStack& stack, Scenario* top) {
  const std::string where_s = stack.files.empty() ? file.string() : stack.files.back();
  if (++stack.loaded > kMaxIncludedFiles)
    throw InputError(where_s, "includes more than " + std::to_string(kMaxIncludedFiles) +
                                  " scenario files in all (includes of includes counted)");
  std::string text;
  try {
    text = readInputFile(file, "scenario file", kMaxYamlFileBytes);
  } catch (const InputError& e) {
    if (stack.files.empty()) throw;
    throw InputError(where_s, std::string("include: ") + e.what());
  }
  const std::string id = std::filesystem::weakly_canonical(file).string();
  if (std::find(stack.files.begin(), stack.files.end(), id) != stack.files.end() ||
      static_cast<int>(stack.files.size()) >= kMaxIncludeDepth) {
    throw InputError(file.string(), "include cycle (or nesting deeper than 16)");
  }
  stack.files.push_back(id);
  if (std::find(stack.read.begin(), stack.read.end(), file) == stack.read.end())
    stack.read.push_back(file);
  CommandProfile profile = parseProfile(text, {YamlDoc(file.string()), file}, stack, top);
  stack.files.pop_back();
  return profile;
}

}  // namespace

Scenario loadScenario(const std::filesystem::path& file) {
  Scenario scenario;
  scenario.source = file;
  IncludeStack stack;
  scenario.profile = loadProfile(file, stack, &scenario);
  scenario.files = std::move(stack.read);
  return scenario;
}

Scenario parseScenario(const std::string& yaml_text, const std::filesystem::path& source) {
  Scenario scenario;
  scenario.source = source;
  IncludeStack stack{{std::filesystem::weakly_canonical(source).string()}, 1, {}};
  scenario.profile = parseProfile(yaml_text, {YamlDoc(source.string()), source}, stack, &scenario);
  scenario.files = std::move(stack.read);
  return scenario;
}

}  // namespace slamprep::sim
