// What a world holds only for a moment: a disc met at its near root while it is there and not
// before or after, its file read back as written, its errors naming the file and line.
#include "slamprep/sim/physics/transients.hpp"

#include <gtest/gtest.h>

#include "slamprep/core/error.hpp"
#include "slamprep/sim/physics/world.hpp"
#include "test_util.hpp"

namespace slamprep::sim {
namespace {

using test::writeTemp;

TEST(Transients, ARayMeetsADiscAtItsNearRoot) {
  // From the origin along +x, a disc of radius 0.5 at (3, 0.3): 3 - sqrt(0.25 - 0.09) = 2.6.
  EXPECT_NEAR(*rayDisc({0, 0}, {1, 0}, {3.0, 0.3}, 0.5), 2.6, 1e-12);
  EXPECT_FALSE(rayDisc({0, 0}, {1, 0}, {3.0, 0.6}, 0.5));   // passes beside it
  EXPECT_FALSE(rayDisc({0, 0}, {-1, 0}, {3.0, 0.0}, 0.5));  // behind the ray
  EXPECT_FALSE(rayDisc({3, 0}, {1, 0}, {3.0, 0.0}, 0.5));   // starts inside it
}

TEST(Transients, ADiscIsSeenOnlyWhileItIsThere) {
  TransientCaster caster({{2.0, 3.0, {5.0, 0.0}, 0.1}, {0.0, 10.0, {0.0, 4.0}, 0.2}});
  const Eigen::Vector2d o(0, 0), east(1, 0), north(0, 1);
  EXPECT_FALSE(caster.castRay(o, east, 1.0, 30.0));
  EXPECT_NEAR(*caster.castRay(o, north, 1.0, 30.0), 3.8, 1e-12);
  EXPECT_NEAR(*caster.castRay(o, east, 2.5, 30.0), 4.9, 1e-12);
  EXPECT_FALSE(caster.castRay(o, east, 2.5, 4.0));  // beyond the range
  EXPECT_FALSE(caster.castRay(o, east, 3.5, 30.0));
  EXPECT_TRUE(caster.castRay(o, north, 9.0, 30.0));
  // Asked again earlier (a scan read before the last one ended): what was there then.
  EXPECT_NEAR(*caster.castRay(o, east, 2.9, 30.0), 4.9, 1e-12);
  EXPECT_FALSE(caster.castRay(o, east, 1.9, 30.0));
}

TEST(Transients, TheFileReadsBackAsWritten) {
  const std::vector<Transient> written{{0.5, 0.6, {1.25, -2.5}, 0.05}, {1.0, 1.0, {0, 0}, 0.3}};
  const auto path = writeTemp("transients.csv", transientsCsv(written));
  const std::vector<Transient> read = loadTransients(path);
  ASSERT_EQ(read.size(), 2u);
  EXPECT_EQ(read[0].center_m, written[0].center_m);
  EXPECT_EQ(read[1].to_s, 1.0);
  EXPECT_EQ(read[1].radius_m, 0.3);
  // A world file names it beside itself.
  EXPECT_EQ(loadWorld(writeTemp("moving_room.yaml",
                                "walls:\n  - {from: [0, 0], to: [1, 0]}\n"
                                "transients_file: transients.csv\n"))
                .transients.size(),
            2u);
}

std::string loadError(const std::string& text) {
  try {
    loadTransients(writeTemp("bad_transients.csv", text));
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(Transients, ErrorsNameTheFileAndLine) {
  const std::string header = "from_s,to_s,x_m,y_m,radius_m\n";
  EXPECT_NE(loadError("t,x,y\n").find("bad_transients.csv:1: expected the header"),
            std::string::npos);
  EXPECT_NE(loadError(header + "0,1,2,3,0.1\n0,1,x,3,0.1\n").find(":3: 'x' is not a finite"),
            std::string::npos)
      << loadError(header + "0,1,2,3,0.1\n0,1,x,3,0.1\n");
  EXPECT_NE(loadError(header + "0,1,2,3\n").find(":2: expected 5"), std::string::npos);
  EXPECT_NE(loadError(header + "2,1,2,3,0.1\n").find("from_s must not exceed to_s"),
            std::string::npos);
  EXPECT_NE(loadError(header + "0,1,2,3,0\n").find("radius_m must be in (0, 10]"),
            std::string::npos);
  EXPECT_NE(loadError("").find("expected the header"), std::string::npos);
}

}  // namespace
}  // namespace slamprep::sim
