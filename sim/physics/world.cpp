#include "sim/physics/world.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <numbers>
#include <set>
#include <sstream>

#include "core/error.hpp"

namespace slamprep::sim {
namespace {

/// Where a node sits: "file:line: key" (yaml-cpp marks are 0-based).
struct Context {
  std::string file;
  std::string where(const YAML::Node& node, const std::string& key) const {
    const YAML::Mark mark = node.Mark();
    std::ostringstream out;
    out << file;
    if (!mark.is_null()) out << ":" << mark.line + 1;
    out << ": " << key;
    return out.str();
  }
  [[noreturn]] void fail(const YAML::Node& node, const std::string& key,
                         const std::string& what) const {
    throw InputError(where(node, key), what);
  }
};

void requireMap(const Context& ctx, const YAML::Node& node, const std::string& key) {
  if (!node.IsMap()) ctx.fail(node, key, "expected a mapping {key: value, ...}");
}

/// Rejects keys of `node` that are not in `allowed`.
void checkKeys(const Context& ctx, const YAML::Node& node, const std::string& key,
               const std::set<std::string>& allowed) {
  for (const auto& entry : node) {
    const std::string name = entry.first.as<std::string>();
    if (!allowed.contains(name)) {
      std::string list;
      for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
      ctx.fail(entry.first, key.empty() ? name : key + "." + name,
               "unknown key '" + name + "' (allowed: " + list + ")");
    }
  }
}

double readNumber(const Context& ctx, const YAML::Node& node, const std::string& key) {
  if (!node.IsScalar()) ctx.fail(node, key, "expected a number");
  double value = 0.0;
  try {
    value = node.as<double>();
  } catch (const YAML::BadConversion&) {
    ctx.fail(node, key, "expected a number, got '" + node.Scalar() + "'");
  }
  if (!std::isfinite(value)) ctx.fail(node, key, "must be finite");
  return value;
}

double readPositive(const Context& ctx, const YAML::Node& node, const std::string& key) {
  const double value = readNumber(ctx, node, key);
  if (value <= 0.0) ctx.fail(node, key, "must be positive, got " + node.Scalar());
  return value;
}

/// An optional positive field: the default when the key is absent.
double optionalPositive(const Context& ctx, const YAML::Node& parent, const std::string& name,
                        const std::string& key, double fallback) {
  const YAML::Node node = parent[name];
  return node ? readPositive(ctx, node, key + "." + name) : fallback;
}

Eigen::Vector2d readPoint(const Context& ctx, const YAML::Node& node, const std::string& key) {
  if (!node.IsSequence() || node.size() != 2) ctx.fail(node, key, "expected a point [x, y]");
  return {readNumber(ctx, node[0], key + "[0]"), readNumber(ctx, node[1], key + "[1]")};
}

const YAML::Node required(const Context& ctx, const YAML::Node& parent, const std::string& name,
                          const std::string& key) {
  const YAML::Node node = parent[name];
  if (!node) ctx.fail(parent, key + "." + name, "missing required key '" + name + "'");
  return node;
}

/// Calls parse(item, "key[i]") for every entry of the optional sequence `root[key]`.
template <typename Parse>
void forEachItem(const Context& ctx, const YAML::Node& root, const std::string& key, Parse parse) {
  const YAML::Node list = root[key];
  if (!list || list.IsNull()) return;
  if (!list.IsSequence()) ctx.fail(list, key, "expected a list");
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string item_key = key + "[" + std::to_string(i) + "]";
    requireMap(ctx, list[i], item_key);
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

Wall parseWall(const Context& ctx, const YAML::Node& node, const std::string& key) {
  checkKeys(ctx, node, key, {"from", "to", "thickness", "height"});
  Wall wall;
  wall.from_m = readPoint(ctx, required(ctx, node, "from", key), key + ".from");
  wall.to_m = readPoint(ctx, required(ctx, node, "to", key), key + ".to");
  if ((wall.to_m - wall.from_m).norm() < 1e-9) ctx.fail(node, key, "'from' and 'to' coincide");
  wall.thickness_m = optionalPositive(ctx, node, "thickness", key, wall.thickness_m);
  wall.height_m = optionalPositive(ctx, node, "height", key, wall.height_m);
  return wall;
}

Box parseBox(const Context& ctx, const YAML::Node& node, const std::string& key) {
  checkKeys(ctx, node, key, {"center", "size", "yaw_deg", "height"});
  const Eigen::Vector2d c = readPoint(ctx, required(ctx, node, "center", key), key + ".center");
  const YAML::Node yaw = node["yaw_deg"];
  const double yaw_deg = yaw ? readNumber(ctx, yaw, key + ".yaw_deg") : 0.0;
  Box box;
  box.T_world_box = SE2(c.x(), c.y(), yaw_deg * std::numbers::pi / 180.0);
  const YAML::Node size = required(ctx, node, "size", key);
  if (!size.IsSequence() || size.size() != 2)
    ctx.fail(size, key + ".size", "expected [size_x, size_y]");
  box.size_m = {readPositive(ctx, size[0], key + ".size[0]"),
                readPositive(ctx, size[1], key + ".size[1]")};
  box.height_m = optionalPositive(ctx, node, "height", key, box.height_m);
  return box;
}

Cylinder parseCylinder(const Context& ctx, const YAML::Node& node, const std::string& key) {
  checkKeys(ctx, node, key, {"center", "radius", "height"});
  Cylinder cyl;
  cyl.center_m = readPoint(ctx, required(ctx, node, "center", key), key + ".center");
  cyl.radius_m = readPositive(ctx, required(ctx, node, "radius", key), key + ".radius");
  cyl.height_m = optionalPositive(ctx, node, "height", key, cyl.height_m);
  return cyl;
}

Polygon parsePolygon(const Context& ctx, const YAML::Node& node, const std::string& key) {
  checkKeys(ctx, node, key, {"vertices", "height"});
  const YAML::Node list = required(ctx, node, "vertices", key);
  if (!list.IsSequence()) ctx.fail(list, key + ".vertices", "expected a list of points [x, y]");
  Polygon poly;
  for (std::size_t i = 0; i < list.size(); ++i)
    poly.vertices_m.push_back(
        readPoint(ctx, list[i], key + ".vertices[" + std::to_string(i) + "]"));
  if (const std::string problem = polygonProblem(poly.vertices_m); !problem.empty())
    ctx.fail(list, key + ".vertices", "degenerate polygon: " + problem);
  poly.height_m = optionalPositive(ctx, node, "height", key, poly.height_m);
  return poly;
}

SE2 parseStart(const Context& ctx, const YAML::Node& node) {
  requireMap(ctx, node, "start");
  checkKeys(ctx, node, "start", {"x", "y", "yaw_deg"});
  const double x = readNumber(ctx, required(ctx, node, "x", "start"), "start.x");
  const double y = readNumber(ctx, required(ctx, node, "y", "start"), "start.y");
  const YAML::Node yaw = node["yaw_deg"];
  const double yaw_deg = yaw ? readNumber(ctx, yaw, "start.yaw_deg") : 0.0;
  return SE2(x, y, yaw_deg * std::numbers::pi / 180.0);
}

YAML::Node loadYaml(const std::filesystem::path& file) {
  try {
    return YAML::LoadFile(file.string());
  } catch (const YAML::BadFile&) {
    throw InputError(file.string(), "cannot open world file");
  } catch (const YAML::Exception& e) {
    throw InputError(file.string() + ":" + std::to_string(e.mark.line + 1),
                     "YAML syntax error: " + e.msg);
  }
}

}  // namespace

World loadWorld(const std::filesystem::path& file) {
  const Context ctx{file.string()};
  const YAML::Node root = loadYaml(file);
  if (!root.IsMap()) throw InputError(file.string(), "expected a mapping at the top level");
  checkKeys(ctx, root, "", {"name", "start", "walls", "boxes", "cylinders", "polygons"});
  World world;
  world.source = file;
  world.name = file.stem().string();
  if (const YAML::Node name = root["name"]) {
    if (!name.IsScalar()) ctx.fail(name, "name", "expected a string");
    world.name = name.Scalar();
  }
  if (const YAML::Node start = root["start"]) world.T_world_start = parseStart(ctx, start);
  forEachItem(ctx, root, "walls", [&](const YAML::Node& n, const std::string& k) {
    world.walls.push_back(parseWall(ctx, n, k));
  });
  forEachItem(ctx, root, "boxes", [&](const YAML::Node& n, const std::string& k) {
    world.boxes.push_back(parseBox(ctx, n, k));
  });
  forEachItem(ctx, root, "cylinders", [&](const YAML::Node& n, const std::string& k) {
    world.cylinders.push_back(parseCylinder(ctx, n, k));
  });
  forEachItem(ctx, root, "polygons", [&](const YAML::Node& n, const std::string& k) {
    world.polygons.push_back(parsePolygon(ctx, n, k));
  });
  if (world.walls.empty() && world.boxes.empty() && world.cylinders.empty() &&
      world.polygons.empty())
    throw InputError(file.string(), "world has no geometry (walls, boxes, cylinders, polygons)");
  return world;
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

}  // namespace slamprep::sim
