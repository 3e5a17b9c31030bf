// People about the robot: where the disc is, a beam meets it at the near root; the same seed gives
// the same people whenever they are asked for; none leave the simulation as it was.
#include "slamprep/sim/drive/people.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace slamprep::sim {
namespace {

/// Rays from the robot every 0.1 deg at time t: the nearest range of each, nullopt for none.
std::vector<std::optional<double>> fan(People& people, double t_s) {
  std::vector<std::optional<double>> out;
  for (int k = 0; k < 3600; ++k) {
    const double a = k * std::numbers::pi / 1800.0;
    out.push_back(people.castRay({0.0, 0.0}, {std::cos(a), std::sin(a)}, {0.0, 0.0}, t_s, 30.0));
  }
  return out;
}

// One person: the fan meets one arc, as wide as a disc of its radius at its distance subtends,
// and its nearest range is the distance less the radius, at least kNearestM away.
TEST(People, OnePersonIsADiscAtItsOffset) {
  PeopleConfig config;
  config.count = 1;
  config.radius_m = 0.2;
  People people(config, 42);
  const auto ranges = fan(people, 3.0);
  int hits = 0;
  double nearest = 1e9;
  for (const auto& r : ranges)
    if (r) ++hits, nearest = std::min(nearest, *r);
  ASSERT_GT(hits, 0);
  const double centre = nearest + config.radius_m;  // the ray through the centre meets it first
  EXPECT_GE(centre, People::kNearestM - 1e-3);
  const double width_deg = 2.0 * std::asin(config.radius_m / centre) * 180.0 / std::numbers::pi;
  EXPECT_NEAR(hits * 0.1, width_deg, 0.25);
}

// The offsets are drawn on a fixed grid: asked every 10 ms or once, the people at 7.3 s are the
// same; and they move (a person 5 s later is elsewhere).
TEST(People, TheSameSeedGivesTheSamePeopleWheneverAsked) {
  PeopleConfig config;
  config.count = 3;
  People often(config, 7), once(config, 7), later(config, 7);
  for (double t = 0.0; t < 7.3; t += 0.01) fan(often, t);
  EXPECT_EQ(fan(often, 7.3), fan(once, 7.3));
  fan(later, 7.3);
  EXPECT_NE(fan(later, 12.3), fan(once, 7.3));
}

TEST(People, NoneMeetNothing) {
  People none(PeopleConfig{}, 1);
  for (const auto& r : fan(none, 1.0)) EXPECT_FALSE(r);
}

}  // namespace
}  // namespace slamprep::sim
