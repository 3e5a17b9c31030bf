#include "slamprep/sim/physics/world.hpp"

#include <gtest/gtest.h>

#include <numbers>

#include "slamprep/core/error.hpp"
#include "slamprep/sim/physics/scene.hpp"
#include "test_util.hpp"

namespace slamprep::sim {
namespace {

using test::worldFile;
using test::writeTemp;

TEST(World, LoadsShippedWorlds) {
  for (const char* name : {"room.yaml", "corridor.yaml", "hall.yaml", "box_room.yaml"}) {
    const World world = loadWorld(worldFile(name));
    EXPECT_FALSE(world.name.empty()) << name;
    EXPECT_EQ(world.source, worldFile(name));
    EXPECT_FALSE(outline(world).empty()) << name;
    // The start pose leaves room for the robot (footprint radius 0.3 m).
    EXPECT_FALSE(Scene(world).collides(world.T_world_start.translation(), 0.3)) << name;
  }
  const World room = loadWorld(worldFile("room.yaml"));
  EXPECT_EQ(room.name, "room");
  EXPECT_EQ(room.walls.size(), 8u);
  EXPECT_EQ(room.boxes.size(), 5u);
  EXPECT_EQ(room.cylinders.size(), 3u);
  EXPECT_EQ(room.polygons.size(), 2u);
  EXPECT_DOUBLE_EQ(room.T_world_start.x, 5.0);
  EXPECT_DOUBLE_EQ(room.T_world_start.y, 4.0);
  // Rotated box: yaw_deg 30 -> rad.
  EXPECT_NEAR(room.boxes[3].T_world_box.yaw, std::numbers::pi / 6, 1e-15);
}

// The brief: room.yaml leaves room to drive ~3 m in any direction from its start pose. A robot
// footprint disc of 0.3 m (chassis corner at 0.27 m) swept 3 m along 32 headings stays clear.
TEST(World, RoomStartLeavesThreeMetresEveryWay) {
  const World room = loadWorld(worldFile("room.yaml"));
  const Scene scene(room);
  const Eigen::Vector2d start = room.T_world_start.translation();
  for (int k = 0; k < 32; ++k) {
    const double a = 2 * std::numbers::pi * k / 32;
    for (double s = 0.0; s <= 3.0; s += 0.05)
      ASSERT_FALSE(scene.collides(start + s * Eigen::Vector2d(std::cos(a), std::sin(a)), 0.3))
          << "heading " << a << " at " << s << " m";
  }
}

TEST(World, OutlineClosesEveryPolyline) {
  const World room = loadWorld(worldFile("room.yaml"));
  const auto lines = outline(room);
  EXPECT_EQ(lines.size(), 8u + 5u + 3u + 2u);
  for (const auto& line : lines) {
    ASSERT_GE(line.size(), 4u);
    EXPECT_EQ(line.front(), line.back());
  }
  // A wall outline is its footprint: 0.15 m thick along the south wall.
  EXPECT_NEAR((lines[0][3] - lines[0][0]).norm(), 0.15, 1e-12);
}

/// Loads `yaml` from a temp file and returns the InputError message ("" when none is thrown).
std::string loadError(const std::string& name, const std::string& yaml) {
  try {
    loadWorld(writeTemp(name, yaml));
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

const char* kWall = "walls:\n  - {from: [0, 0], to: [1, 0]}\n";

TEST(WorldErrors, UnknownTopLevelKeyNamesFileLineAndKey) {
  const std::string msg = loadError("unknown_top.yaml", std::string(kWall) + "colour: red\n");
  EXPECT_NE(msg.find("unknown_top.yaml:3:1: colour"), std::string::npos) << msg;
  EXPECT_NE(msg.find("unknown key"), std::string::npos) << msg;
}

TEST(WorldErrors, UnknownNestedKeyNamesItsPath) {
  const std::string msg =
      loadError("unknown_nested.yaml",
                "name: x\nwalls:\n  - {from: [0, 0], to: [1, 0]}\n  - {from: [0, 0], to: [0, 1], "
                "thikness: 0.2}\n");
  EXPECT_NE(msg.find("unknown_nested.yaml:4:32: walls[1].thikness"), std::string::npos) << msg;
}

TEST(WorldErrors, WrongTypeNamesKeyAndLine) {
  const std::string msg =
      loadError("wrong_type.yaml",
                std::string(kWall) + "cylinders:\n  - center: [1, 1]\n" + "    radius: wide\n");
  EXPECT_NE(msg.find("wrong_type.yaml:5:13: cylinders[0].radius"), std::string::npos) << msg;
  EXPECT_NE(msg.find("expected a finite number, got 'wide'"), std::string::npos) << msg;
  const std::string point =
      loadError("wrong_point.yaml", "walls:\n  - {from: [0, 0, 0], to: [1, 0]}\n");
  EXPECT_NE(point.find("wrong_point.yaml:2:12: walls[0].from"), std::string::npos) << point;
}

TEST(WorldErrors, NonPositiveSizes) {
  const std::string box =
      loadError("zero_box.yaml", "boxes:\n  - {center: [0, 0], size: [1.0, 0.0]}\n");
  EXPECT_NE(box.find("zero_box.yaml:2:34: boxes[0].size[1]"), std::string::npos) << box;
  EXPECT_NE(box.find("must be positive"), std::string::npos) << box;
  const std::string wall =
      loadError("neg_wall.yaml", "walls:\n  - {from: [0, 0], to: [1, 0], height: -2}\n");
  EXPECT_NE(wall.find("neg_wall.yaml:2:40: walls[0].height"), std::string::npos) << wall;
  const std::string zero_len =
      loadError("zero_wall.yaml", "walls:\n  - {from: [1, 1], to: [1, 1]}\n");
  EXPECT_NE(zero_len.find("zero_wall.yaml:2:5: walls[0]"), std::string::npos) << zero_len;
}

TEST(WorldErrors, DegeneratePolygons) {
  const std::string two = loadError("poly_two.yaml", "polygons:\n  - vertices: [[0, 0], [1, 0]]\n");
  EXPECT_NE(two.find("poly_two.yaml:2:15: polygons[0].vertices"), std::string::npos) << two;
  EXPECT_NE(two.find("at least 3"), std::string::npos) << two;
  const std::string flat =
      loadError("poly_flat.yaml", "polygons:\n  - vertices: [[0, 0], [1, 0], [2, 0]]\n");
  EXPECT_NE(flat.find("zero area"), std::string::npos) << flat;
  const std::string bowtie =
      loadError("poly_bowtie.yaml", "polygons:\n  - vertices: [[0, 0], [2, 2], [2, 0], [0, 1]]\n");
  EXPECT_NE(bowtie.find("self-intersecting"), std::string::npos) << bowtie;
  const std::string repeated =
      loadError("poly_closed.yaml", "polygons:\n  - vertices: [[0, 0], [1, 0], [1, 1], [0, 0]]\n");
  EXPECT_NE(repeated.find("coincide"), std::string::npos) << repeated;
}

TEST(WorldErrors, MissingKeysFilesAndSyntax) {
  const std::string missing = loadError("missing.yaml", "cylinders:\n  - {center: [0, 0]}\n");
  EXPECT_NE(missing.find("missing.yaml:2:5: cylinders[0].radius"), std::string::npos) << missing;
  const std::string empty = loadError("empty.yaml", "name: nothing\n");
  EXPECT_NE(empty.find("no geometry"), std::string::npos) << empty;
  const std::string syntax = loadError("syntax.yaml", "walls:\n  - {from: [0, 0}\n");
  EXPECT_NE(syntax.find("syntax.yaml:2:"), std::string::npos) << syntax;
  const std::string start =
      loadError("start.yaml", std::string(kWall) + "start: {x: 1, y: 2, yaw: 3}\n");
  EXPECT_NE(start.find("start.yaml:3:21: start.yaw"), std::string::npos) << start;
  EXPECT_THROW(loadWorld("/nonexistent/world.yaml"), InputError);
}

// Sizes and coordinates beyond 10 km (kMaxSize_m, kMaxCoordinate_m) are typos: 1e300 used to be
// accepted. Each case names the key and the bound.
TEST(WorldErrors, AbsurdSizesAndCoordinatesNameTheKeyAndTheBound) {
  struct Case {
    std::string yaml, key, bound;
  };
  const std::string size = "must be positive and at most 10000, got ";
  const std::string coordinate = "must be between -10000 and 10000, got ";
  const std::vector<Case> cases = {
      {"cylinders:\n  - {center: [0, 0], radius: 1e300}\n", "cylinders[0].radius", size},
      {"cylinders:\n  - {center: [0, 0], radius: 10001}\n", "cylinders[0].radius", size},
      {"cylinders:\n  - {center: [0, 2e4], radius: 1}\n", "cylinders[0].center[1]", coordinate},
      {"boxes:\n  - {center: [0, 0], size: [1, 1e5]}\n", "boxes[0].size[1]", size},
      {"boxes:\n  - {center: [0, 0], size: [1, 1], yaw_deg: 1e300}\n", "boxes[0].yaw_deg",
       "must be between -360 and 360, got "},
      {"walls:\n  - {from: [-1e300, 0], to: [1, 0]}\n", "walls[0].from[0]", coordinate},
      {"walls:\n  - {from: [0, 0], to: [1, 0], thickness: 1e9}\n", "walls[0].thickness", size},
      {"walls:\n  - {from: [0, 0], to: [1, 0], height: 1e300}\n", "walls[0].height", size},
      {"polygons:\n  - vertices: [[0, 0], [1e5, 0], [0, 1]]\n", "polygons[0].vertices[1][0]",
       coordinate},
      {std::string(kWall) + "start: {x: 1e300, y: 0}\n", "start.x", coordinate},
  };
  for (const Case& c : cases) {
    const std::string msg = loadError("absurd.yaml", c.yaml);
    EXPECT_NE(msg.find("absurd.yaml:"), std::string::npos) << c.yaml << msg;
    EXPECT_NE(msg.find(": " + c.key + ": " + c.bound), std::string::npos) << c.yaml << msg;
  }
  // The bound itself is accepted: a 10 km wall.
  EXPECT_EQ(loadError("big.yaml", "walls:\n  - {from: [-5000, 0], to: [5000, 0]}\n"), "");
}

// yaml-cpp's own exceptions (BadConversion for a key that is a list or a mapping, found by
// fuzz_world) used to escape; every one is an InputError naming the file, line and column.
TEST(WorldErrors, KeysThatAreNotNamesAreInputErrors) {
  const std::string flow = loadError("flow_key.yaml", "{[]}");
  EXPECT_NE(flow.find("flow_key.yaml:1:2: key: expected a plain key"), std::string::npos) << flow;
  const std::string map_key = loadError("map_key.yaml", std::string(kWall) + "{a: 1}: 2\n");
  EXPECT_NE(map_key.find("map_key.yaml:3:1"), std::string::npos) << map_key;
  const std::string nested =
      loadError("nested_key.yaml", "walls:\n  - {[1]: 2, from: [0, 0], to: [1, 0]}\n");
  EXPECT_NE(nested.find("nested_key.yaml:2:6: walls[0]: expected a plain key"), std::string::npos)
      << nested;
  const std::string name = loadError("name.yaml", std::string(kWall) + "name: [a]\n");
  EXPECT_NE(name.find("name.yaml:3:7: name: expected a string"), std::string::npos) << name;
}

}  // namespace
}  // namespace slamprep::sim
