#include "slamprep/eval/formats/yaml_tree.hpp"

#include <algorithm>
#include <utility>
#include <vector>

#include "slamprep/core/error.hpp"

namespace slamprep::eval {
namespace {

using KeyMarks = std::vector<std::pair<const std::string*, YAML::Mark>>;

/// "file:line:col" (1-based), or "file" for a null mark. Appended piecewise: GCC 12 warns falsely
/// (-Wrestrict) on ":" + std::string.
std::string at(const std::string& file, const YAML::Mark& mark) {
  std::string out = file;
  if (mark.is_null()) return out;
  out.append(":").append(std::to_string(mark.line + 1));
  out.append(":").append(std::to_string(mark.column + 1));
  return out;
}

/// A mapping's keys: refuses one that appears twice ("walls:" twice used to keep the first only).
/// `keys` is scratch space, reused across mappings (most have a handful of keys).
void checkUniqueKeys(const YAML::Node& map, const std::string& file, KeyMarks& keys) {
  keys.clear();
  for (const auto& entry : map) {
    if (!entry.first.IsScalar()) continue;  // the reader refuses it where the key is read
    keys.emplace_back(&entry.first.Scalar(), yamlMark(entry.first));
  }
  if (keys.size() > 1)
    std::stable_sort(keys.begin(), keys.end(),
                     [](const auto& a, const auto& b) { return *a.first < *b.first; });
  for (std::size_t i = 1; i < keys.size(); ++i)
    if (*keys[i].first == *keys[i - 1].first) {
      const auto& [first, second] = keys[i - 1].second.pos <= keys[i].second.pos
                                        ? std::pair(keys[i - 1].second, keys[i].second)
                                        : std::pair(keys[i].second, keys[i - 1].second);
      throw InputError(at(file, second).append(": ").append(*keys[i].first),
                       "key appears twice in one mapping (first on line " +
                           std::to_string(first.line + 1) + ")");
    }
}

}  // namespace

YAML::Mark yamlMark(const YAML::Node& node) {
  try {
    return node.Mark();
  } catch (const YAML::Exception&) {  // an invalid (zombie) node has no position
    return YAML::Mark::null_mark();
  }
}

void checkYamlTree(const YAML::Node& root, const std::string& file) {
  std::vector<std::pair<YAML::Node, int>> stack{{root, 1}};
  KeyMarks keys;
  std::size_t visited = 0;
  while (!stack.empty()) {
    const auto [node, depth] = stack.back();
    stack.pop_back();
    if (++visited > kMaxYamlNodes)
      throw InputError(file, "more than " + std::to_string(kMaxYamlNodes) +
                                 " YAML nodes (aliases count every time they are used)");
    if (!node.IsMap() && !node.IsSequence()) continue;
    if (depth > kMaxYamlDepth)
      throw InputError(at(file, yamlMark(node)),
                       "YAML nested deeper than " + std::to_string(kMaxYamlDepth) + " levels");
    if (node.IsMap()) checkUniqueKeys(node, file, keys);
    for (const auto& entry : node) {
      if (node.IsSequence()) {
        stack.emplace_back(entry, depth + 1);
      } else {
        stack.emplace_back(entry.first, depth + 1);
        stack.emplace_back(entry.second, depth + 1);
      }
    }
  }
}

}  // namespace slamprep::eval
