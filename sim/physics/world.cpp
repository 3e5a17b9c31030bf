#include "slamprep/sim/physics/world.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <numbers>

#include "slamprep/core/error.hpp"
#include "slamprep/sim/yaml/yaml_fields.hpp"

namespace slamprep::sim {
namespace {

// World sizes are checked against bounds no real environment reaches: coordinates and sizes
// beyond 10 km are typos (1e300 used to pass and only failed, by luck, in simulate's start check).
constexpr double kMaxCoordinate_m = 1e4;  ///< |x|, |y| of every point
constexpr double kMaxSize_m = 1e4;        ///< lengths: thickness, height, radius, box sizes
const Bounds kCoordinate{-kMaxCoordinate_m, kMaxCoordinate_m};
const Bounds kSize{0.0, kMaxSize_m, true};
const Bounds kYaw{-360.0, 360.0};  ///< yaw_deg
// Objects in one world (walls, boxes, cylinders, polygons, floor patches together): the path check
// and the scene set-up grow faster than linearly in their number (10^5 walls took minutes), and
// a hand-made or converted floor plan of 10^4 objects is already a large building.
constexpr std::size_t kMaxObjects = 10000;
// Outline vertices of all polygons and floor patches together: each outline's simplicity check
// is quadratic in its vertices (at most 10^4 each), so 2 * 10^4 in all bounds it at 10^8 tests.
constexpr std::size_t kMaxOutlineVertices = 20000;

/// An optional size field: the default when the key is absent.
double optionalSize(const YamlDoc& doc, const YAML::Node& parent, const std::string& name,
                    const std::string& key, double fallback) {
  return doc.optionalNumber(parent, name, key, fallback, kSize);
}

Eigen::Vector2d requiredPoint(const YamlDoc& doc, const YAML::Node& node, const std::string& name,
                              const std::string& key) {
  return doc.point(doc.required(node, name, key), key + "." + name, kCoordinate);
}

/// Calls parse(item, "key[i]") for every entry of the optional sequence `root[key]`; `objects`
/// counts the entries of all lists, refused beyond kMaxObjects before any is parsed.
template <typename Parse>
void forEachItem(const YamlDoc& doc, const YAML::Node& root, const std::string& key,
                 std::size_t& objects, Parse parse) {
  const YAML::Node list = root[key];
  if (!list || list.IsNull()) return;
  if (!list.IsSequence()) doc.fail(list, key, "expected a list");
  objects += list.size();
  if (objects > kMaxObjects)
    doc.fail(list, key,
             "the world has more than " + std::to_string(kMaxObjects) +
                 " objects (walls, boxes, cylinders, polygons and floor patches together)");
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string item_key = key + "[" + std::to_string(i) + "]";
    doc.requireMap(list[i], item_key);
    parse(list[i], item_key);
  }
}

double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

/// True when closed segments p1-p2 and q1-q2 intersect (touching counts).
bool segmentsIntersect(const Eigen::Vector2d& p1, const Eigen::Vector2d& p2,
                       const Eigen::Vector2d& q1, const Eigen::Vector2d& q2) {
  const double d1 = cross(p2 - p1, q1 - p1), d2 = cross(p2 - p1, q2 - p1);
  const double d3 = cross(q2 - q1, p1 - q1), d4 = cross(q2 - q1, p2 - q1);
  if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0)))
    return true;
  auto onSegment = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& p,
                      double d) {
    return d == 0.0 && p.x() >= std::min(a.x(), b.x()) && p.x() <= std::max(a.x(), b.x()) &&
           p.y() >= std::min(a.y(), b.y()) && p.y() <= std::max(a.y(), b.y());
  };
  return onSegment(p1, p2, q1, d1) || onSegment(p1, p2, q2, d2) || onSegment(q1, q2, p1, d3) ||
         onSegment(q1, q2, p2, d4);
}

/// Shoelace formula: twice the signed area (positive counter-clockwise).
double twiceSignedArea(const std::vector<Eigen::Vector2d>& v) {
  double sum = 0.0;
  for (std::size_t i = 0; i < v.size(); ++i) sum += cross(v[i], v[(i + 1) % v.size()]);
  return sum;
}

/// Empty when the polygon is simple with positive area, else what is wrong.
std::string polygonProblem(const std::vector<Eigen::Vector2d>& v) {
  const std::size_t n = v.size();
  if (n < 3) return "needs at least 3 vertices, got " + std::to_string(n);
  for (std::size_t i = 0; i < n; ++i)
    if ((v[i] - v[(i + 1) % n]).norm() < 1e-9)
      return "vertices " + std::to_string(i) + " and " + std::to_string((i + 1) % n) +
             " coincide (do not repeat the first vertex at the end)";
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j) {
      const bool adjacent = j == i + 1 || (i == 0 && j == n - 1);
      if (!adjacent && segmentsIntersect(v[i], v[(i + 1) % n], v[j], v[(j + 1) % n]))
        return "edges " + std::to_string(i) + " and " + std::to_string(j) +
               " intersect (self-intersecting outline)";
    }
  if (std::abs(twiceSignedArea(v)) < 1e-9) return "has zero area (collinear vertices)";
  return {};
}

/// The optional `returns` flag of an object: false makes it glass.
bool parseReturns(const YamlDoc& doc, const YAML::Node& node, const std::string& key) {
  const YAML::Node value = node["returns"];
  if (!value) return true;
  const std::string text = value.IsScalar() ? value.Scalar() : "";
  if (text != "true" && text != "false")
    doc.fail(value, key + ".returns", "expected true or false");
  return text == "true";
}

std::vector<Eigen::Vector2d> parseOutline(const YamlDoc& doc, const YAML::Node& list,
                                          const std::string& key, std::size_t& vertices_so_far) {
  if (!list.IsSequence()) doc.fail(list, key, "expected a list of points [x, y]");
  // polygonProblem is O(n^2): 10^4 vertices (10^8 pair tests) is far beyond any hand-made world.
  constexpr std::size_t kMaxVertices = 10000;
  if (list.size() > kMaxVertices)
    doc.fail(list, key, "more than " + std::to_string(kMaxVertices) + " vertices");
  vertices_so_far += list.size();
  if (vertices_so_far > kMaxOutlineVertices)
    doc.fail(list, key,
             "the polygons and floor patches have more than " +
                 std::to_string(kMaxOutlineVertices) + " vertices in all");
  std::vector<Eigen::Vector2d> vertices;
  for (std::size_t i = 0; i < list.size(); ++i)
    vertices.push_back(doc.point(list[i], key + "[" + std::to_string(i) + "]", kCoordinate));
  if (const std::string problem = polygonProblem(vertices); !problem.empty())
    doc.fail(list, key, "degenerate polygon: " + problem);
  return vertices;
}

Wall parseWall(const YamlDoc& doc, const YAML::Node& node, const std::string& key) {
  doc.checkKeys(node, key, {"from", "to", "thickness", "height", "returns"});
  Wall wall;
  wall.from_m = requiredPoint(doc, node, "from", key);
  wall.to_m = requiredPoint(doc, node, "to", key);
  if ((wall.to_m - wall.from_m).norm() < 1e-9) doc.fail(node, key, "'from' and 'to' coincide");
  wall.thickness_m = optionalSize(doc, node, "thickness", key, wall.thickness_m);
  wall.height_m = optionalSize(doc, node, "height", key, wall.height_m);
  wall.returns = parseReturns(doc, node, key);
  return wall;
}

Box parseBox(const YamlDoc& doc, const YAML::Node& node, const std::string& key) {
  doc.checkKeys(node, key, {"center", "size", "yaw_deg", "height", "returns"});
  const Eigen::Vector2d c = requiredPoint(doc, node, "center", key);
  const double yaw_deg = doc.optionalNumber(node, "yaw_deg", key, 0.0, kYaw);
  Box box;
  box.T_world_box = SE2(c.x(), c.y(), yaw_deg * std::numbers::pi / 180.0);
  const YAML::Node size = doc.required(node, "size", key);
  if (!size.IsSequence() || size.size() != 2)
    doc.fail(size, key + ".size", "expected [size_x, size_y]");
  box.size_m = {doc.number(size[0], key + ".size[0]", kSize),
                doc.number(size[1], key + ".size[1]", kSize)};
  box.height_m = optionalSize(doc, node, "height", key, box.height_m);
  box.returns = parseReturns(doc, node, key);
  return box;
}

Cylinder parseCylinder(const YamlDoc& doc, const YAML::Node& node, const std::string& key) {
  doc.checkKeys(node, key, {"center", "radius", "height", "returns"});
  Cylinder cyl;
  cyl.center_m = requiredPoint(doc, node, "center", key);
  cyl.radius_m = doc.number(doc.required(node, "radius", key), key + ".radius", kSize);
  cyl.height_m = optionalSize(doc, node, "height", key, cyl.height_m);
  cyl.returns = parseReturns(doc, node, key);
  return cyl;
}

Polygon parsePolygon(const YamlDoc& doc, const YAML::Node& node, const std::string& key,
                     std::size_t& vertices) {
  doc.checkKeys(node, key, {"vertices", "height", "returns"});
  Polygon poly;
  poly.vertices_m =
      parseOutline(doc, doc.required(node, "vertices", key), key + ".vertices", vertices);
  poly.height_m = optionalSize(doc, node, "height", key, poly.height_m);
  poly.returns = parseReturns(doc, node, key);
  return poly;
}

FloorPatch parseFloorPatch(const YamlDoc& doc, const YAML::Node& node, const std::string& key,
                           std::size_t& vertices) {
  doc.checkKeys(node, key, {"outline", "friction"});
  FloorPatch patch;
  patch.outline_m =
      parseOutline(doc, doc.required(node, "outline", key), key + ".outline", vertices);
  patch.friction = doc.number(doc.required(node, "friction", key), key + ".friction",
                              Bounds{0.0, 10.0});  // Bullet clamps combined friction at 10
  return patch;
}

SE2 parseStart(const YamlDoc& doc, const YAML::Node& node) {
  doc.requireMap(node, "start");
  doc.checkKeys(node, "start", {"x", "y", "yaw_deg"});
  const double x = doc.number(doc.required(node, "x", "start"), "start.x", kCoordinate);
  const double y = doc.number(doc.required(node, "y", "start"), "start.y", kCoordinate);
  const double yaw_deg = doc.optionalNumber(node, "yaw_deg", "start", 0.0, kYaw);
  return SE2(x, y, yaw_deg * std::numbers::pi / 180.0);
}

World parseWorld(const YamlDoc& doc, const YAML::Node& root, const std::filesystem::path& file) {
  if (!root.IsMap()) throw InputError(file.string(), "expected a mapping at the top level");
  doc.checkKeys(root, "",
                {"name", "start", "walls", "boxes", "cylinders", "polygons", "floor_patches",
                 "transients_file"});
  World world;
  world.source = file;
  world.name = file.stem().string();
  if (const YAML::Node name = root["name"]) world.name = doc.string(name, "name");
  if (const YAML::Node start = root["start"]) world.T_world_start = parseStart(doc, start);
  std::size_t objects = 0, vertices = 0;
  forEachItem(doc, root, "walls", objects, [&](const YAML::Node& n, const std::string& k) {
    world.walls.push_back(parseWall(doc, n, k));
  });
  forEachItem(doc, root, "boxes", objects, [&](const YAML::Node& n, const std::string& k) {
    world.boxes.push_back(parseBox(doc, n, k));
  });
  forEachItem(doc, root, "cylinders", objects, [&](const YAML::Node& n, const std::string& k) {
    world.cylinders.push_back(parseCylinder(doc, n, k));
  });
  forEachItem(doc, root, "polygons", objects, [&](const YAML::Node& n, const std::string& k) {
    world.polygons.push_back(parsePolygon(doc, n, k, vertices));
  });
  forEachItem(doc, root, "floor_patches", objects, [&](const YAML::Node& n, const std::string& k) {
    world.floor_patches.push_back(parseFloorPatch(doc, n, k, vertices));
  });
  // Beside the world file, as a scenario's paths are: a twin's folder moves as one.
  if (const YAML::Node t = root["transients_file"])
    world.transients = loadTransients(file.parent_path() / doc.string(t, "transients_file"));
  if (world.walls.empty() && world.boxes.empty() && world.cylinders.empty() &&
      world.polygons.empty())
    throw InputError(file.string(), "world has no geometry (walls, boxes, cylinders, polygons)");
  return world;
}

}  // namespace

World loadWorld(const std::filesystem::path& file) {
  const YamlDoc doc(file.string());
  const YAML::Node root = loadYamlFile(file, doc, "world file");
  return doc.guard([&] { return parseWorld(doc, root, file); });
}

std::vector<Eigen::Vector2d> footprint(const Wall& wall) {
  const Eigen::Vector2d along = (wall.to_m - wall.from_m).normalized();
  const Eigen::Vector2d side = Eigen::Vector2d(-along.y(), along.x()) * (wall.thickness_m / 2);
  return {wall.from_m - side, wall.to_m - side, wall.to_m + side, wall.from_m + side};
}

std::vector<Eigen::Vector2d> footprint(const Box& box) {
  const Eigen::Vector2d h = box.size_m / 2;
  return {box.T_world_box * Eigen::Vector2d(-h.x(), -h.y()),
          box.T_world_box * Eigen::Vector2d(h.x(), -h.y()),
          box.T_world_box * Eigen::Vector2d(h.x(), h.y()),
          box.T_world_box * Eigen::Vector2d(-h.x(), h.y())};
}

std::vector<std::vector<Eigen::Vector2d>> outline(const World& world) {
  std::vector<std::vector<Eigen::Vector2d>> lines;
  auto closed = [&](std::vector<Eigen::Vector2d> ring) {
    ring.push_back(ring.front());
    lines.push_back(std::move(ring));
  };
  for (const Wall& wall : world.walls) closed(footprint(wall));
  for (const Box& box : world.boxes) closed(footprint(box));
  constexpr int kSegments = 48;
  for (const Cylinder& cyl : world.cylinders) {
    std::vector<Eigen::Vector2d> ring;
    for (int k = 0; k < kSegments; ++k) {
      const double a = 2 * std::numbers::pi * k / kSegments;
      ring.push_back(cyl.center_m + cyl.radius_m * Eigen::Vector2d(std::cos(a), std::sin(a)));
    }
    closed(std::move(ring));
  }
  for (const Polygon& poly : world.polygons) closed(poly.vertices_m);
  return lines;
}

bool insidePolygon(const std::vector<Eigen::Vector2d>& polygon, const Eigen::Vector2d& p) {
  bool inside = false;
  for (std::size_t i = 0, j = polygon.size() - 1; i < polygon.size(); j = i++) {
    const Eigen::Vector2d& a = polygon[i];
    const Eigen::Vector2d& b = polygon[j];
    // Crossing number: edges that straddle the horizontal line through p, right of p.
    if ((a.y() > p.y()) != (b.y() > p.y()) &&
        p.x() < a.x() + (p.y() - a.y()) * (b.x() - a.x()) / (b.y() - a.y()))
      inside = !inside;
  }
  return inside;
}

}  // namespace slamprep::sim
