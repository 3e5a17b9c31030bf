#include "slamprep/eval/formats/rosbag2.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <string>
#include <utility>

#include "slamprep/core/error.hpp"
#include "slamprep/core/input_file.hpp"
#include "slamprep/eval/formats/yaml_tree.hpp"

namespace slamprep::eval {
namespace fs = std::filesystem;
namespace {

std::string scalarOr(const YAML::Node& node, const char* key, const std::string& fallback) {
  const YAML::Node v = node[key];
  return v && v.IsScalar() ? v.as<std::string>() : fallback;
}

BagStorageKind storageOf(const std::string& id, const std::string& where) {
  if (const auto kind = findName(kBagStorageNames, id)) return *kind;
  throw InputError(where, "storage_identifier \"" + id + "\" is not read (only " +
                              joinedNames(kBagStorageNames, " and ") + ")");
}

BagCompressionMode compressionOf(const std::string& mode, const std::string& format,
                                 const std::string& where) {
  const auto found = mode.empty() ? BagCompressionMode::kNone  // early bags leave it out
                                  : findName(kBagCompressionModeNames, mode);
  if (!found)
    throw InputError(where, "compression_mode \"" + mode + "\" is unknown (" +
                                joinedNames(kBagCompressionModeNames, ", ") + ")");
  const BagCompressionMode m = *found;
  if (m != BagCompressionMode::kNone && format != "zstd")
    throw InputError(where, "compression_format \"" + format + "\" (compression_mode " + mode +
                                ") is not read (only zstd, what rosbag2 ships)");
  return m;
}

/// A storage file's kind from its name with any ".zstd" dropped: .db3 or .mcap.
std::optional<BagStorageKind> kindFromName(fs::path name) {
  if (name.extension() == ".zstd") name.replace_extension();
  if (name.extension() == ".db3") return BagStorageKind::kSqlite3;
  if (name.extension() == ".mcap") return BagStorageKind::kMcap;
  return std::nullopt;
}

/// A split file's number: rosbag2 names them NAME_0, NAME_1, ... (before the extensions).
std::pair<std::string, long> splitIndex(const fs::path& file) {
  std::string stem = file.filename().string();
  stem = stem.substr(0, stem.find('.'));
  const std::size_t digits = stem.find_last_not_of("0123456789") + 1;
  const std::string number = stem.substr(digits);
  return {stem.substr(0, digits), number.empty() || number.size() > 9 ? -1 : std::stol(number)};
}

/// The storage files `dir` holds, in split order (_2 before _10): what a renamed bag's
/// metadata.yaml no longer names.
std::vector<fs::path> heldFiles(const fs::path& dir) {
  std::vector<fs::path> held;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.is_regular_file() && kindFromName(e.path().filename())) held.push_back(e.path());
  std::sort(held.begin(), held.end(), [](const fs::path& a, const fs::path& b) {
    return std::pair(splitIndex(a), a) < std::pair(splitIndex(b), b);
  });
  return held;
}

std::string namesOf(const std::vector<fs::path>& files) {
  std::string names;
  for (const fs::path& f : files) names += (names.empty() ? "" : ", ") + f.filename().string();
  return names;
}

/// A listed file in `dir`, or nothing where it is missing.
std::optional<fs::path> listedFile(const fs::path& dir, const YAML::Node& p,
                                   const std::string& where) {
  if (!p.IsScalar()) throw InputError(where, "relative_file_paths: an entry is not a name");
  const fs::path relative = p.as<std::string>();
  fs::path file = dir / relative;
  // Older rosbag2 versions wrote the bag folder's name in front of each file.
  if (!fs::exists(file) && relative.has_parent_path()) file = dir / relative.filename();
  if (!fs::is_regular_file(file)) return std::nullopt;
  return file;
}

/// The storage files metadata.yaml lists; where none is present and the folder holds as many of
/// one kind (a bag whose folder and files were renamed), those, with a note.
std::vector<fs::path> storageFiles(const fs::path& dir, const YAML::Node& paths,
                                   const std::string& where, std::vector<std::string>& notes) {
  std::vector<fs::path> found;
  std::vector<std::string> missing;
  for (const YAML::Node& p : paths) {
    if (const auto file = listedFile(dir, p, where))
      found.push_back(*file);
    else
      missing.push_back(p.as<std::string>());
  }
  if (missing.empty()) return found;
  const std::vector<fs::path> held = heldFiles(dir);
  const bool one_kind = std::all_of(held.begin(), held.end(), [&](const fs::path& f) {
    return kindFromName(f.filename()) == kindFromName(held.front().filename());
  });
  if (found.empty() && !held.empty() && held.size() == paths.size() && one_kind) {
    notes.push_back("metadata.yaml lists " + std::to_string(missing.size()) +
                    " storage file(s) the folder does not hold (" + missing.front() +
                    (missing.size() > 1 ? ", ..." : "") + "): read " + namesOf(held) +
                    " instead, the folder's own (a renamed bag)");
    return held;
  }
  throw InputError(where, "relative_file_paths: " + missing.front() + " not found in " +
                              dir.string() +
                              (held.empty() ? "" : " (it holds " + namesOf(held) + ")"));
}

Rosbag2Bag fromMetadata(const fs::path& dir, const YAML::Node& root, const std::string& where) {
  const YAML::Node info = root["rosbag2_bagfile_information"];
  if (!info || !info.IsMap()) throw InputError(where, "no rosbag2_bagfile_information mapping");
  Rosbag2Bag bag;
  bag.path = dir;
  const std::string version = scalarOr(info, "version", "0");
  bag.version = std::atoi(version.c_str());
  bag.compression_format = scalarOr(info, "compression_format", "");
  bag.compression =
      compressionOf(scalarOr(info, "compression_mode", ""), bag.compression_format, where);
  const YAML::Node paths = info["relative_file_paths"];
  if (!paths || !paths.IsSequence() || paths.size() == 0)
    throw InputError(where, "relative_file_paths: missing or empty");
  bag.files = storageFiles(dir, paths, where, bag.notes);
  bag.storage_identifier = scalarOr(info, "storage_identifier", "");
  // Early bags (version 1-2) may leave it empty: the files' extension says.
  if (bag.storage_identifier.empty())
    if (const auto k = kindFromName(bag.files.front()))
      bag.storage_identifier = std::string(storageName(*k));
  bag.storage = storageOf(bag.storage_identifier, where);
  return bag;
}

/// The first bytes of `file`.
std::string magicOf(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::string head(16, '\0');
  in.read(head.data(), 16);
  head.resize(static_cast<std::size_t>(in.gcount()));
  return head;
}

/// One storage file without metadata.yaml: SQLite or MCAP by magic, a zstd frame by magic (then
/// the name without ".zstd" says which storage), else by extension.
Rosbag2Bag fromFile(const fs::path& file) {
  Rosbag2Bag bag;
  bag.path = file;
  bag.files = {file};
  const std::string head = magicOf(file);
  std::optional<BagStorageKind> kind;
  if (head.rfind(std::string("SQLite format 3\0", 16), 0) == 0) {
    kind = BagStorageKind::kSqlite3;
  } else if (head.rfind("\x89MCAP", 0) == 0) {
    kind = BagStorageKind::kMcap;
  } else if (head.rfind("\x28\xb5\x2f\xfd", 0) == 0) {
    bag.compression = BagCompressionMode::kFile;
    bag.compression_format = "zstd";
    kind = kindFromName(file);
    if (!kind)
      throw InputError(file.string(), "a zstd-compressed file not named *.db3.zstd or *.mcap.zstd");
  } else {
    kind = kindFromName(file);  // let the storage reader say what is wrong with it
  }
  if (!kind) throw InputError(file.string(), "neither an SQLite (.db3) nor an MCAP (.mcap) file");
  bag.storage = *kind;
  bag.storage_identifier = std::string(storageName(*kind));
  return bag;
}

}  // namespace

std::string_view storageName(BagStorageKind k) {
  return nameOf(kBagStorageNames, k);
}

std::string_view compressionModeName(BagCompressionMode m) {
  return nameOf(kBagCompressionModeNames, m);
}

Rosbag2Bag readRosbag2(const fs::path& bag) {
  if (!fs::exists(bag)) throw InputError(bag.string(), "no such file or folder");
  if (!fs::is_directory(bag)) return fromFile(bag);
  const fs::path yaml = bag / "metadata.yaml";
  if (!fs::is_regular_file(yaml))
    throw InputError(bag.string(),
                     "a bag folder needs its metadata.yaml (which lists the storage files in "
                     "order): give one .db3 or .mcap file instead, or rebuild it with "
                     "`ros2 bag reindex " +
                         bag.string() + " sqlite3` (or mcap)");
  try {
    // Read whole first: a device or an oversized file is refused before yaml-cpp sees it.
    const YAML::Node metadata = YAML::Load(readInputFile(yaml, "bag metadata", kMaxYamlFileBytes));
    checkYamlTree(metadata, yaml.string());
    return fromMetadata(bag, metadata, yaml.string());
  } catch (const YAML::Exception& e) {
    throw InputError(yaml.string() + ":" + std::to_string(e.mark.line + 1), e.msg);
  }
}

}  // namespace slamprep::eval
