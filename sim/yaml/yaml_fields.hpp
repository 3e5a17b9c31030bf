#pragma once
// Reading YAML input files (worlds, scenarios, suites) with one error policy: every refusal is an
// InputError whose location is "file:line:col: key" (1-based line and column of the node), typed
// reads check finiteness and ranges, unknown keys are named, and no yaml-cpp exception escapes
// (YamlDoc::guard turns any of them into an InputError naming the file and line).

#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "slamprep/eval/formats/yaml_tree.hpp"

namespace slamprep::sim {

// The tree limits every YAML input shares (eval/formats/yaml_tree.hpp).
using eval::kMaxYamlDepth;
using eval::kMaxYamlNodes;

/// Inclusive bounds of a number read from YAML.
struct Bounds {
  double min = -std::numeric_limits<double>::max();  ///< smallest accepted value
  double max = std::numeric_limits<double>::max();   ///< largest accepted value
  bool positive = false;                             ///< also require > 0 (not just >= min)
};

/// One YAML document being read: its file name for messages, and the typed, checked reads.
class YamlDoc {
 public:
  explicit YamlDoc(std::string file) : file_(std::move(file)) {}

  const std::string& file() const { return file_; }

  /// "file:line:col: key" for `node` (1-based); "file: key" when the node has no position.
  std::string where(const YAML::Node& node, std::string_view key) const;
  /// "file:line: key": the whole line, for messages about an entry found after parsing.
  std::string whereLine(const YAML::Node& node, std::string_view key) const;
  [[noreturn]] void fail(const YAML::Node& node, std::string_view key,
                         const std::string& what) const;

  /// Runs `read()` and turns any YAML::Exception escaping it into InputError("file:line:col").
  template <typename Read>
  auto guard(Read&& read) const -> decltype(read()) {
    try {
      return read();
    } catch (const YAML::Exception& e) {
      rethrow(e);
    }
  }
  /// The InputError for a yaml-cpp exception: its position in this file and its message.
  [[noreturn]] void rethrow(const YAML::Exception& e) const;

  // ---- structure ------------------------------------------------------------------------------

  void requireMap(const YAML::Node& node, std::string_view key) const;
  /// A mapping key as a string; refuses keys that are not plain scalars ({[]}: 1, {}: 2, ~: 3).
  std::string keyName(const YAML::Node& key_node, std::string_view parent) const;
  /// Refuses keys of the mapping `node` not in `allowed`, naming "prefix.key" and the list.
  /// `prefix` is the mapping's own key ("" at the top level).
  void checkKeys(const YAML::Node& node, std::string_view prefix,
                 const std::set<std::string>& allowed) const;
  /// map[name], refusing its absence ("missing required key").
  YAML::Node required(const YAML::Node& map, const std::string& name,
                      std::string_view prefix) const;

  // ---- values ---------------------------------------------------------------------------------

  /// A finite number inside `bounds`.
  double number(const YAML::Node& node, std::string_view key, const Bounds& bounds = {}) const;
  /// A whole number in [min, max].
  std::int64_t integer(const YAML::Node& node, std::string_view key, std::int64_t min,
                       std::int64_t max) const;
  /// A scalar as text.
  std::string string(const YAML::Node& node, std::string_view key) const;
  /// true or false (YAML's spellings: true/false, yes/no, on/off); anything else is an error.
  bool boolean(const YAML::Node& node, std::string_view key) const;
  /// A scalar or a list of scalars as text.
  std::vector<std::string> stringList(const YAML::Node& node, std::string_view key) const;
  /// [x, y] with both coordinates inside `bounds`.
  Eigen::Vector2d point(const YAML::Node& node, std::string_view key,
                        const Bounds& bounds = {}) const;

  /// map[name] read by `number`, or `fallback` when the key is absent.
  double optionalNumber(const YAML::Node& map, const std::string& name, std::string_view prefix,
                        double fallback, const Bounds& bounds = {}) const;

 private:
  std::string file_;
};

/// Parses `text`; a syntax error is InputError("file:line:col", "malformed YAML: ..."), and so
/// are nesting beyond kMaxYamlDepth, more than kMaxYamlNodes nodes and a key repeated in one
/// mapping.
YAML::Node parseYaml(const std::string& text, const YamlDoc& doc);
/// Reads and parses `path`; a missing file is InputError(path, "cannot open <what>"), and so is a
/// device, a FIFO, a folder or a file over kMaxYamlFileBytes (core/input_file.hpp).
YAML::Node loadYamlFile(const std::filesystem::path& path, const YamlDoc& doc,
                        std::string_view what);

/// "prefix.name", or "name" when prefix is empty.
std::string joinKey(std::string_view prefix, std::string_view name);

}  // namespace slamprep::sim
