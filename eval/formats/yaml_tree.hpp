#pragma once
// The checks every YAML input passes before a reader walks it (worlds, scenarios, suites, bag
// metadata): nesting depth, node count with aliases counted at each use, and keys repeated in
// one mapping (yaml-cpp would keep one of them silently).

#include <yaml-cpp/yaml.h>

#include <cstddef>
#include <string>

namespace slamprep::eval {

/// Mappings and lists nested deeper than this are refused (slamprep's files use at most 4).
inline constexpr int kMaxYamlDepth = 64;
/// Nodes in one document, an alias counted every time it is used (a "billion laughs" file is a
/// few hundred bytes); a world of 10 000 walls has about 100 000.
inline constexpr std::size_t kMaxYamlNodes = 1000000;

/// The node's position, or a null mark for nodes without one (absent or invalid nodes).
YAML::Mark yamlMark(const YAML::Node& node);

/// Depth first without recursion, every node once per use: InputError naming `file` (and the
/// line and column) for nesting beyond kMaxYamlDepth, more than kMaxYamlNodes nodes, or a key
/// that appears twice in one mapping.
void checkYamlTree(const YAML::Node& root, const std::string& file);

}  // namespace slamprep::eval
