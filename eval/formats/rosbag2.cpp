#include "eval/formats/rosbag2.hpp"

#include <yaml-cpp/yaml.h>

#include "core/error.hpp"

namespace slamprep::eval {
namespace fs = std::filesystem;
namespace {

std::string scalarOr(const YAML::Node& node, const char* key, const std::string& fallback) {
  const YAML::Node v = node[key];
  return v && v.IsScalar() ? v.as<std::string>() : fallback;
}

std::vector<fs::path> listedFiles(const fs::path& dir, const YAML::Node& root,
                                  const std::string& where) {
  const YAML::Node info = root["rosbag2_bagfile_information"];
  if (!info || !info.IsMap()) throw InputError(where, "no rosbag2_bagfile_information mapping");
  const std::string storage = scalarOr(info, "storage_identifier", "");
  if (storage != "mcap")
    throw InputError(where, "storage_identifier \"" + storage +
                                "\": only mcap bags are read (convert others with "
                                "`ros2 bag convert`)");
  if (scalarOr(info, "compression_mode", "") == "FILE")
    throw InputError(where, "the bag's files are compressed whole (compression_mode FILE, " +
                                scalarOr(info, "compression_format", "?") +
                                "): decompress them first, or record with chunk compression");
  const YAML::Node paths = info["relative_file_paths"];
  if (!paths || !paths.IsSequence() || paths.size() == 0)
    throw InputError(where, "relative_file_paths: missing or empty");
  std::vector<fs::path> files;
  for (const YAML::Node& p : paths) {
    if (!p.IsScalar()) throw InputError(where, "relative_file_paths: an entry is not a name");
    const fs::path relative = p.as<std::string>();
    fs::path file = dir / relative;
    // Older rosbag2 versions wrote the bag folder's name in front of each file.
    if (!fs::exists(file) && relative.has_parent_path()) file = dir / relative.filename();
    if (!fs::is_regular_file(file))
      throw InputError(
          where, "relative_file_paths: " + relative.string() + " not found in " + dir.string());
    files.push_back(file);
  }
  return files;
}

}  // namespace

std::vector<fs::path> bagFiles(const fs::path& bag) {
  if (!fs::exists(bag)) throw InputError(bag.string(), "no such file or folder");
  if (!fs::is_directory(bag)) return {bag};
  const fs::path yaml = bag / "metadata.yaml";
  if (!fs::is_regular_file(yaml))
    throw InputError(bag.string(),
                     "a bag folder needs its metadata.yaml (which lists the .mcap files in "
                     "order): give one .mcap file instead, or rebuild it with "
                     "`ros2 bag reindex " +
                         bag.string() + " mcap`");
  try {
    return listedFiles(bag, YAML::LoadFile(yaml.string()), yaml.string());
  } catch (const YAML::Exception& e) {
    throw InputError(yaml.string() + ":" + std::to_string(e.mark.line + 1), e.msg);
  }
}

}  // namespace slamprep::eval
