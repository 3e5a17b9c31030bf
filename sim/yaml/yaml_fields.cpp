#include "slamprep/sim/yaml/yaml_fields.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <utility>
#include <vector>

#include "slamprep/core/error.hpp"
#include "slamprep/core/input_file.hpp"
#include "slamprep/eval/formats/yaml_tree.hpp"

namespace slamprep::sim {
namespace {

/// Shortest text that reads back as `value`.
std::string formatNumber(double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

/// "got '<scalar>'" or "got a list/a mapping/null" for messages about the wrong type.
std::string got(const YAML::Node& node) {
  if (!node.IsDefined()) return "nothing";
  switch (node.Type()) {
    case YAML::NodeType::Scalar:
      return "'" + node.Scalar() + "'";
    case YAML::NodeType::Sequence:
      return "a list";
    case YAML::NodeType::Map:
      return "a mapping";
    default:
      return "null";
  }
}

/// Appends ":line" or ":line:col" (1-based) unless the mark is null. Appended piecewise: GCC 12
/// warns falsely (-Wrestrict) on ":" + std::string.
void appendPosition(std::string& out, const YAML::Mark& mark, bool with_column) {
  if (mark.is_null()) return;
  out.append(":").append(std::to_string(mark.line + 1));
  if (with_column) out.append(":").append(std::to_string(mark.column + 1));
}

std::string describe(const Bounds& bounds) {
  const bool has_min = bounds.min > -std::numeric_limits<double>::max();
  const bool has_max = bounds.max < std::numeric_limits<double>::max();
  if (bounds.positive)
    return has_max ? "must be positive and at most " + formatNumber(bounds.max)
                   : "must be positive";
  if (has_min && has_max)
    return "must be between " + formatNumber(bounds.min) + " and " + formatNumber(bounds.max);
  return has_min ? "must be at least " + formatNumber(bounds.min)
                 : "must be at most " + formatNumber(bounds.max);
}

}  // namespace

std::string joinKey(std::string_view prefix, std::string_view name) {
  if (prefix.empty()) return std::string(name);
  return std::string(prefix).append(".").append(name);
}

std::string YamlDoc::where(const YAML::Node& node, std::string_view key) const {
  const YAML::Mark mark = eval::yamlMark(node);
  std::string out = file_;
  appendPosition(out, mark, true);
  if (!key.empty()) out.append(": ").append(key);
  return out;
}

std::string YamlDoc::whereLine(const YAML::Node& node, std::string_view key) const {
  const YAML::Mark mark = eval::yamlMark(node);
  std::string out = file_;
  appendPosition(out, mark, false);
  if (!key.empty()) out.append(": ").append(key);
  return out;
}

void YamlDoc::fail(const YAML::Node& node, std::string_view key, const std::string& what) const {
  throw InputError(where(node, key), what);
}

void YamlDoc::rethrow(const YAML::Exception& e) const {
  std::string at = file_;
  appendPosition(at, e.mark, true);
  const bool syntax = dynamic_cast<const YAML::ParserException*>(&e) != nullptr;
  throw InputError(at, (syntax ? "malformed YAML: " : "unexpected YAML content: ") + e.msg);
}

void YamlDoc::requireMap(const YAML::Node& node, std::string_view key) const {
  if (!node.IsMap()) fail(node, key, "expected a mapping {key: value, ...}, got " + got(node));
}

std::string YamlDoc::keyName(const YAML::Node& key_node, std::string_view parent) const {
  if (!key_node.IsScalar())
    fail(key_node, parent.empty() ? "key" : parent, "expected a plain key, got " + got(key_node));
  return key_node.Scalar();
}

void YamlDoc::checkKeys(const YAML::Node& node, std::string_view prefix,
                        const std::set<std::string>& allowed) const {
  for (const auto& entry : node) {
    const std::string name = keyName(entry.first, prefix);
    if (allowed.contains(name)) continue;
    std::string list;
    for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
    fail(entry.first, joinKey(prefix, name), "unknown key '" + name + "' (allowed: " + list + ")");
  }
}

YAML::Node YamlDoc::required(const YAML::Node& map, const std::string& name,
                             std::string_view prefix) const {
  const YAML::Node node = map[name];
  if (!node) fail(map, joinKey(prefix, name), "missing required key '" + name + "'");
  return node;
}

double YamlDoc::number(const YAML::Node& node, std::string_view key, const Bounds& bounds) const {
  double value = 0.0;
  if (!node.IsScalar() || !YAML::convert<double>::decode(node, value) || !std::isfinite(value))
    fail(node, key, "expected a finite number, got " + got(node));
  if (value < bounds.min || value > bounds.max || (bounds.positive && value <= 0.0))
    fail(node, key, describe(bounds) + ", got " + node.Scalar());
  return value;
}

std::int64_t YamlDoc::integer(const YAML::Node& node, std::string_view key, std::int64_t min,
                              std::int64_t max) const {
  const std::string range =
      "expected a whole number between " + std::to_string(min) + " and " + std::to_string(max);
  if (!node.IsScalar()) fail(node, key, range + ", got " + got(node));
  std::int64_t value = 0;
  if (!YAML::convert<std::int64_t>::decode(node, value)) {
    // "1e3" or "2.0": whole numbers written as floating point.
    double x = 0.0;
    if (!YAML::convert<double>::decode(node, x) || !std::isfinite(x) || x != std::floor(x) ||
        x < static_cast<double>(min) || x > static_cast<double>(max))
      fail(node, key, range + ", got " + got(node));
    value = static_cast<std::int64_t>(x);
  }
  if (value < min || value > max) fail(node, key, range + ", got " + got(node));
  return value;
}

std::string YamlDoc::string(const YAML::Node& node, std::string_view key) const {
  if (!node.IsScalar()) fail(node, key, "expected a string, got " + got(node));
  return node.Scalar();
}

bool YamlDoc::boolean(const YAML::Node& node, std::string_view key) const {
  bool value = false;
  if (!node.IsScalar() || !YAML::convert<bool>::decode(node, value))
    fail(node, key, "expected true or false, got " + got(node));
  return value;
}

std::vector<std::string> YamlDoc::stringList(const YAML::Node& node, std::string_view key) const {
  if (node.IsScalar()) return {node.Scalar()};
  if (!node.IsSequence()) fail(node, key, "expected a list of strings, got " + got(node));
  std::vector<std::string> out;
  for (std::size_t i = 0; i < node.size(); ++i)
    out.push_back(string(node[i], std::string(key) + "[" + std::to_string(i) + "]"));
  return out;
}

Eigen::Vector2d YamlDoc::point(const YAML::Node& node, std::string_view key,
                               const Bounds& bounds) const {
  if (!node.IsSequence() || node.size() != 2)
    fail(node, key, "expected a point [x, y], got " + got(node));
  const std::string k(key);
  return {number(node[0], k + "[0]", bounds), number(node[1], k + "[1]", bounds)};
}

double YamlDoc::optionalNumber(const YAML::Node& map, const std::string& name,
                               std::string_view prefix, double fallback,
                               const Bounds& bounds) const {
  const YAML::Node node = map[name];
  return node ? number(node, joinKey(prefix, name), bounds) : fallback;
}

YAML::Node parseYaml(const std::string& text, const YamlDoc& doc) {
  try {
    YAML::Node root = YAML::Load(text);
    eval::checkYamlTree(root, doc.file());
    return root;
  } catch (const YAML::Exception& e) {
    doc.rethrow(e);
  }
}

YAML::Node loadYamlFile(const std::filesystem::path& path, const YamlDoc& doc,
                        std::string_view what) {
  return parseYaml(readInputFile(path, what, kMaxYamlFileBytes), doc);
}

}  // namespace slamprep::sim
