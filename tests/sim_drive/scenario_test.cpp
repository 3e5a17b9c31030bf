#include "slamprep/sim/drive/scenario.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

#include "slamprep/core/error.hpp"
#include "slamprep/tests/support/scratch_dir.hpp"

namespace slamprep::sim {
namespace {

const std::filesystem::path kScenarios =
    std::filesystem::path(SLAMPREP_SOURCE_DIR) / "worlds" / "scenarios";

/// Integral of the command over the whole profile (exact: piecewise linear).
Eigen::Vector2d integral(const CommandProfile& profile) {
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  profile.forEachPiece(0.0, profile.duration_s() + 1.0,
                       [&](CommandKind, const Eigen::Vector2d& c0, const Eigen::Vector2d& c1,
                           double dt) { sum += 0.5 * dt * (c0 + c1); });
  return sum;
}

/// Largest |d command / dt| between consecutive knots, per component.
Eigen::Vector2d maxSlope(const CommandProfile& profile) {
  Eigen::Vector2d worst = Eigen::Vector2d::Zero();
  for (const ProfileSegment& s : profile.segments()) {
    for (std::size_t k = 0; k + 1 < s.knots.size(); ++k) {
      const double dt = s.knots[k + 1].t_s - s.knots[k].t_s;
      EXPECT_GT(dt, 0.0) << s.where;
      worst = worst.cwiseMax((s.knots[k + 1].value - s.knots[k].value).cwiseAbs() / dt);
    }
  }
  return worst;
}

std::string errorOf(const std::string& yaml) {
  try {
    parseScenario(yaml, "test.yaml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(Scenario, StraightCoversItsDistanceWithinTheLimits) {
  const Scenario s = parseScenario(
      "limits: {linear_accel_mps2: 0.5}\n"
      "segments:\n  - {type: straight, distance_m: 2.0, speed_mps: 0.5}\n",
      "t.yaml");
  // Trapezoid: ramp 1 s, hold 3 s, ramp 1 s; area 0.5 * 4 = 2 m.
  EXPECT_NEAR(s.profile.duration_s(), 5.0, 1e-12);
  EXPECT_NEAR(integral(s.profile).x(), 2.0, 1e-12);
  EXPECT_NEAR(maxSlope(s.profile).x(), 0.5, 1e-12);
  EXPECT_NEAR(s.profile.at(2.5).value.x(), 0.5, 1e-12);
  EXPECT_NEAR(s.profile.at(0.5).value.x(), 0.25, 1e-12);
  EXPECT_EQ(s.profile.at(-1.0).value, Eigen::Vector2d::Zero());
  EXPECT_EQ(s.profile.at(6.0).value, Eigen::Vector2d::Zero());
}

TEST(Scenario, ShortSpinBecomesATriangleAndKeepsItsAngle) {
  // 10 deg at 1 rad/s with 2 rad/s^2: the full ramp alone would turn 0.5 * 1 * 0.5 = 0.25 rad
  // > 0.1745 rad, so the peak drops to sqrt(area / ramp) = sqrt(0.1745 / 0.5) rad/s.
  const Scenario s =
      parseScenario("segments:\n  - {type: spin, angle_deg: -10, rate_radps: 1.0}\n", "t.yaml");
  const double angle = 10.0 * std::numbers::pi / 180.0;
  EXPECT_NEAR(integral(s.profile).y(), -angle, 1e-12);
  EXPECT_NEAR(integral(s.profile).x(), 0.0, 1e-15);
  EXPECT_NEAR(maxSlope(s.profile).y(), 2.0, 1e-12);
  EXPECT_NEAR(s.profile.segments()[0].knots[1].value.y(), -std::sqrt(angle / 0.5), 1e-12);
}

TEST(Scenario, ArcByAngleAndByDuration) {
  const Scenario s = parseScenario(
      "segments:\n"
      "  - {type: arc, v_mps: 1.0, w_radps: 1.0, angle_deg: 360}\n"
      "  - {type: arc, v_mps: 0.5, w_radps: -0.2, duration_s: 4}\n",
      "t.yaml");
  ASSERT_EQ(s.profile.segments().size(), 2u);
  const Eigen::Vector2d total = integral(s.profile);
  EXPECT_NEAR(total.x(), 2.0 * std::numbers::pi + 0.5 * 4, 1e-12);
  EXPECT_NEAR(total.y(), 2.0 * std::numbers::pi - 0.2 * 4, 1e-12);
  // v and w ramp together: the curvature w / v is constant inside each segment.
  const Command c = s.profile.at(0.3);
  EXPECT_NEAR(c.value.y() / c.value.x(), 1.0, 1e-12);
}

TEST(Scenario, FigureEightTurnsTwoFullCirclesAndBack) {
  const Scenario s = parseScenario(
      "segments:\n  - {type: figure_eight, radius_m: 1.0, speed_mps: 0.5, loops: 2}\n", "t.yaml");
  const ProfileSegment& seg = s.profile.segments().at(0);
  // Heading over everything is zero. The flip from +W to -W is a ramp centred on the ideal
  // switch, so at its end the heading equals the ideal one: 2 pi - W (t_end_of_flip - t_switch).
  EXPECT_NEAR(integral(s.profile).y(), 0.0, 1e-9);
  const double w = 0.5;  // speed / radius
  const double t_switch = 0.5 * (seg.knots[2].t_s + seg.knots[3].t_s);
  Eigen::Vector2d first = Eigen::Vector2d::Zero();
  s.profile.forEachPiece(0.0, seg.knots[3].t_s,
                         [&](CommandKind, const auto& c0, const auto& c1, double dt) {
                           first += 0.5 * dt * (c0 + c1);
                         });
  EXPECT_NEAR(first.y(), 2.0 * std::numbers::pi - w * (seg.knots[3].t_s - t_switch), 1e-9);
  // Four circles of 2 pi R each: v is constant through the flips, so the length is exact.
  EXPECT_NEAR(integral(s.profile).x(), 4 * 2.0 * std::numbers::pi, 1e-9);
  const Eigen::Vector2d slope = maxSlope(s.profile);
  EXPECT_LE(slope.x(), 1.0 + 1e-12);
  EXPECT_LE(slope.y(), 2.0 + 1e-12);
}

TEST(Scenario, TrackIsItsKnotsRestToRest) {
  const Scenario s = parseScenario(
      "segments:\n  - {type: track, kind: wheel_rates, period_s: 0.5, values: [[1, 2], [3, -1]]}\n",
      "t.yaml");
  ASSERT_EQ(s.profile.segments().size(), 1u);
  EXPECT_EQ(s.profile.segments()[0].kind, CommandKind::wheel_rates);
  EXPECT_DOUBLE_EQ(s.profile.duration_s(), 1.5);  // a zero knot before and after the values
  EXPECT_TRUE(s.profile.at(0.0).value.isZero());
  EXPECT_EQ(s.profile.at(0.5).value, Eigen::Vector2d(1, 2));
  EXPECT_EQ(s.profile.at(0.75).value, Eigen::Vector2d(2, 0.5));  // linear between knots
  EXPECT_TRUE(s.profile.at(1.5).value.isZero());
  // Area under the knots: trapezoids of 0.5 s.
  EXPECT_NEAR(integral(s.profile).x(), 0.5 * (0.5 * 1 + 0.5 * (1 + 3) + 0.5 * 3), 1e-12);
}

TEST(Scenario, TrackRefusesAnUnknownKindAndBadValues) {
  auto parse = [](const std::string& seg) {
    return parseScenario("segments:\n  - {type: track, " + seg + "}\n", "t.yaml");
  };
  EXPECT_THROW(parse("kind: wheels, period_s: 0.1, values: [[1, 2]]"), InputError);
  EXPECT_THROW(parse("kind: twist, period_s: 0, values: [[1, 2]]"), InputError);
  EXPECT_THROW(parse("kind: twist, period_s: 0.1, values: []"), InputError);
  EXPECT_THROW(parse("kind: twist, period_s: 0.1, values: [[1, 2, 3]]"), InputError);
  EXPECT_NO_THROW(parse("kind: twist, period_s: 0.1, values: [[0.1, 0.2]]"));
}

TEST(Scenario, TrackIsOpenLoopUnlessClosedLoopIsAsked) {
  auto parse = [](const std::string& seg) {
    return parseScenario("segments:\n  - {type: track, kind: wheel_rates, period_s: 0.1, " + seg +
                             "values: [[1, 2]]}\n",
                         "t.yaml");
  };
  EXPECT_FALSE(parse("").profile.segments()[0].closed_loop);
  EXPECT_FALSE(parse("closed_loop: false, ").profile.segments()[0].closed_loop);
  const auto defaults = parse("closed_loop: true, ").profile.segments()[0].closed_loop;
  ASSERT_TRUE(defaults);
  EXPECT_EQ(defaults->k_x_per_s, TrackingParams{}.k_x_per_s);
  EXPECT_EQ(defaults->max_wheel_radps, 0.0);  // the knots' largest, found by the controller
  const auto set = parse(
                       "closed_loop: true, k_x_per_s: 1, k_y_per_m2: 4, k_theta_per_m: 3, "
                       "max_wheel_radps: 9, ")
                       .profile.segments()[0]
                       .closed_loop;
  ASSERT_TRUE(set);
  EXPECT_EQ(set->k_x_per_s, 1.0);
  EXPECT_EQ(set->k_y_per_m2, 4.0);
  EXPECT_EQ(set->k_theta_per_m, 3.0);
  EXPECT_EQ(set->max_wheel_radps, 9.0);
  // Gains of an open-loop track would do nothing: refused, as are negative gains and caps.
  EXPECT_THROW(parse("k_x_per_s: 1, "), InputError);
  EXPECT_THROW(parse("closed_loop: false, max_wheel_radps: 9, "), InputError);
  EXPECT_THROW(parse("closed_loop: true, k_y_per_m2: -1, "), InputError);
  EXPECT_THROW(parse("closed_loop: true, max_wheel_radps: 0, "), InputError);
  EXPECT_THROW(parse("closed_loop: yes please, "), InputError);
}

TEST(Scenario, UmbmarkIsFourLegsAndFourRightAngles) {
  const Scenario s = loadScenario(kScenarios / "umbmark_cw.yaml");
  const Eigen::Vector2d total = integral(s.profile);
  EXPECT_NEAR(total.x(), 4 * 2.5, 1e-9);
  EXPECT_NEAR(total.y(), -2.0 * std::numbers::pi, 1e-9);
  // Legs and turns never overlap: v and w are never both non-zero.
  for (double t = 0.0; t < s.profile.duration_s(); t += 0.01) {
    const Eigen::Vector2d c = s.profile.at(t).value;
    EXPECT_TRUE(c.x() == 0.0 || c.y() == 0.0) << "t = " << t;
  }
}

TEST(Scenario, RandomSmoothIsSeededAndRespectsLimits) {
  const std::string a =
      "limits: {linear_accel_mps2: 0.3, angular_accel_radps2: 0.7}\n"
      "segments:\n  - {type: random_smooth, duration_s: 30, interval_s: 0.5, seed: ";
  const Scenario s1 = parseScenario(a + "4}\n", "t.yaml");
  const Scenario s2 = parseScenario(a + "4}\n", "t.yaml");
  const Scenario s3 = parseScenario(a + "5}\n", "t.yaml");
  const auto& k1 = s1.profile.segments()[0].knots;
  const auto& k2 = s2.profile.segments()[0].knots;
  const auto& k3 = s3.profile.segments()[0].knots;
  ASSERT_EQ(k1.size(), 61u);
  bool differs = false;
  for (std::size_t k = 0; k < k1.size(); ++k) {
    EXPECT_EQ(k1[k].value, k2[k].value);  // bit-identical
    differs |= k1[k].value != k3[k].value;
  }
  EXPECT_TRUE(differs);
  const Eigen::Vector2d slope = maxSlope(s1.profile);
  EXPECT_LE(slope.x(), 0.3 + 1e-12);
  EXPECT_LE(slope.y(), 0.7 + 1e-12);
  EXPECT_EQ(k1.back().value, Eigen::Vector2d::Zero());
}

TEST(Scenario, WheelRateSegmentsKeepTheirKind) {
  const Scenario s = parseScenario(
      "segments:\n  - {type: wheel_rates, left_radps: 4, right_radps: 6, duration_s: 2}\n"
      "  - {type: straight, distance_m: -1}\n",
      "t.yaml");
  EXPECT_EQ(s.profile.at(1.0).kind, CommandKind::wheel_rates);
  // Wheel segment: (4, 6) rad/s for an equivalent 2 s; then the straight's v: -1 m.
  EXPECT_NEAR((integral(s.profile) - Eigen::Vector2d(8.0 - 1.0, 12.0)).norm(), 0.0, 1e-12);
  EXPECT_EQ(s.profile.segments()[1].kind, CommandKind::twist);
  EXPECT_LT(s.profile.at(s.profile.duration_s() - 1.0).value.x(), 0.0);  // reverse
}

TEST(Scenario, ShippedScenariosLoadAndStartAndEndAtRest) {
  for (const char* name : {"umbmark_cw", "umbmark_ccw", "arc", "figure_eight", "spin", "straight",
                           "stop_and_go", "random_smooth", "default"}) {
    SCOPED_TRACE(name);
    const Scenario s = loadScenario(kScenarios / (std::string(name) + ".yaml"));
    EXPECT_EQ(s.name, name);
    EXPECT_GT(s.profile.duration_s(), 1.0);
    for (const ProfileSegment& seg : s.profile.segments()) {
      EXPECT_EQ(seg.knots.front().value, Eigen::Vector2d::Zero());
      EXPECT_EQ(seg.knots.back().value, Eigen::Vector2d::Zero());
    }
  }
  // The default scenario is about a minute and turns both ways.
  const Scenario d = loadScenario(kScenarios / "default.yaml");
  EXPECT_GT(d.profile.duration_s(), 50.0);
  EXPECT_LT(d.profile.duration_s(), 70.0);
}

TEST(Scenario, ErrorsNameFileLineAndKey) {
  EXPECT_NE(errorOf("segments: [ {type: straight").find("test.yaml:"), std::string::npos);
  EXPECT_NE(errorOf("segments: [ {type: straight").find("malformed YAML"), std::string::npos);
  const std::string unknown =
      errorOf("segments:\n  - {type: straight, distance_m: 1}\n  - {type: spin, angel_deg: 9}\n");
  EXPECT_NE(unknown.find("test.yaml:3:18: segments[1].angel_deg"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("unknown key"), std::string::npos);
  const std::string negative =
      errorOf("segments:\n  - {type: straight, distance_m: 1, speed_mps: -2}\n");
  EXPECT_NE(negative.find("segments[0].speed_mps"), std::string::npos) << negative;
  EXPECT_NE(negative.find("positive"), std::string::npos);
  EXPECT_NE(errorOf("segments:\n  - {type: fly}\n").find("segments[0].type"), std::string::npos);
  EXPECT_NE(errorOf("name: x\n").find("test.yaml: segments"), std::string::npos);
  EXPECT_NE(errorOf("segments: []\n").find("non-empty"), std::string::npos);
  EXPECT_NE(errorOf("segments:\n  - {type: arc, v_mps: 1, w_radps: 1}\n").find("exactly one"),
            std::string::npos);
  EXPECT_NE(errorOf("limits: {linear_accel_mps2: 0}\nsegments:\n  - {type: stop, duration_s: 1}\n")
                .find("limits.linear_accel_mps2"),
            std::string::npos);
  EXPECT_NE(errorOf("segments:\n  - {type: straight, distance_m: abc}\n").find("finite number"),
            std::string::npos);
  EXPECT_NE(errorOf("segments:\n  - {type: figure_eight, radius_m: 0.01, speed_mps: 2}\n")
                .find("acceleration limits"),
            std::string::npos);
}

TEST(Scenario, IncludeCyclesAreRejected) {
  const test::ScratchDir dir("scenario_include");
  std::ofstream(dir / "a.yaml") << "segments:\n  - {type: include, file: b.yaml}\n";
  std::ofstream(dir / "b.yaml") << "segments:\n  - {type: include, file: a.yaml}\n";
  try {
    loadScenario(dir / "a.yaml");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("include cycle"), std::string::npos) << e.what();
  }
  std::ofstream(dir / "c.yaml") << "segments:\n  - {type: include, file: missing.yaml}\n";
  try {
    loadScenario(dir / "c.yaml");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot open"), std::string::npos) << e.what();
  }
}

// yaml-cpp's own exceptions used to escape for keys and values of the wrong kind ("{}:", found by
// fuzz_scenario, threw YAML::BadConversion); each is now an InputError naming line and column.
TEST(Scenario, KeysAndValuesOfTheWrongKindAreInputErrors) {
  EXPECT_NE(errorOf("{}:").find("test.yaml:1:1: key: expected a plain key, got a mapping"),
            std::string::npos)
      << errorOf("{}:");
  EXPECT_NE(errorOf("segments:\n  - {[a]: 1, type: stop, duration_s: 1}\n")
                .find("test.yaml:2:6: segments[0]: expected a plain key, got a list"),
            std::string::npos);
  const std::string name = errorOf("name: [x]\nsegments:\n  - {type: stop, duration_s: 1}\n");
  EXPECT_NE(name.find("test.yaml:1:7: name: expected a string, got a list"), std::string::npos)
      << name;
  const std::string type = errorOf("segments:\n  - {type: {a: 1}}\n");
  EXPECT_NE(type.find("test.yaml:2:12: segments[0].type: expected a string"), std::string::npos)
      << type;
}

// Sizes that would make the profile absurdly long or large: one day at most in total, counts of
// at most 10^4, random_smooth at most 10^6 knots, other values at most 10^6 (m, m/s, rad/s).
TEST(Scenario, AbsurdSizesAreRefusedNamingTheKey) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"{type: straight, distance_m: 1e300}", "segments[0].distance_m: must be between"},
      {"{type: straight, distance_m: 1, speed_mps: 1e7}", "segments[0].speed_mps: must be"},
      {"{type: umbmark, direction: cw, laps: 100000}", "segments[0].laps: expected a whole"},
      {"{type: stop_and_go, distance_m: 1, repeats: 2.5}", "segments[0].repeats: expected a whole"},
      {"{type: random_smooth, duration_s: 1000, interval_s: 1e-6}", "segments[0].interval_s"},
      {"{type: random_smooth, duration_s: 10, seed: -1}", "segments[0].seed: expected a whole"},
      {"{type: arc, v_mps: 1, w_radps: .inf, duration_s: 1}", "segments[0].w_radps: expected a"},
      // Each segment below a day, together above it: refused at the segment that crosses it.
      {"{type: stop, duration_s: 86400}\n  - {type: stop, duration_s: 1}",
       "test.yaml:3:5: segments[1]: the scenario lasts more than one day"},
  };
  for (const auto& [segment, expected] : cases) {
    const std::string msg = errorOf("segments:\n  - " + segment + "\n");
    EXPECT_NE(msg.find(expected), std::string::npos) << segment << "\n" << msg;
  }
  EXPECT_EQ(errorOf("segments:\n  - {type: stop, duration_s: 86400}\n"), "");
}

}  // namespace
}  // namespace slamprep::sim
