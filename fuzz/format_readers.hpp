#pragma once
// The readers of slamprep::formats behind one call (fuzz/readers.hpp adds the others). Apart so
// that a build linking only slamprep::formats can replay their corpus: the sanitizer subset of
// scripts/test.sh (scripts/sanitize.sh --ci).

#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

#include "slamprep/eval/formats/csv_logs.hpp"
#include "slamprep/eval/formats/dataset_json.hpp"
#include "slamprep/eval/formats/import.hpp"
#include "slamprep/eval/formats/mcap.hpp"
#include "slamprep/eval/formats/relations.hpp"
#include "slamprep/eval/formats/rosbag2.hpp"
#include "slamprep/eval/formats/scan_jsonl.hpp"
#include "slamprep/eval/formats/tum.hpp"
#include "slamprep/tests/support/scratch_dir.hpp"

namespace slamprep::fuzz {

inline const std::vector<std::string>& formatReaderNames() {
  static const std::vector<std::string> names = {"mcap", "carmen", "dataset", "relations", "bag"};
  return names;
}

/// A per-process scratch file for the readers that only take a path (world, suite); its folder
/// is removed when the process exits.
inline std::filesystem::path scratchFile(const char* name) {
  static const test::ScratchDir dir("fuzz");
  return dir / name;
}

inline void writeScratch(const std::filesystem::path& file, std::string_view text) {
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out.write(text.data(), static_cast<std::streamsize>(text.size()));
}

/// Feeds `bytes` to formats reader `name`; false when `name` is not one. Throws whatever the
/// reader throws.
inline bool readFormatAs(const std::string& name, std::string_view bytes) {
  if (name == "mcap") {
    eval::readMcap(bytes, "fuzz.mcap");
    eval::ImportParams params;  // a geometry, so the import goes on past that check
    params.nominal_geometry = DiffDriveParams{};
    eval::importMcap(bytes, "fuzz.mcap", params);
  } else if (name == "carmen") {
    eval::importCarmen(bytes, "fuzz.clf");
  } else if (name == "dataset") {
    // The first byte picks the dataset file parser.
    if (bytes.empty()) return true;
    const std::string_view text = bytes.substr(1);
    switch (static_cast<unsigned char>(bytes[0]) % 5) {
      case 0:
        eval::parseTum(text, "fuzz.tum");
        break;
      case 1:
        eval::parseEncoders(text, "encoders.csv");
        break;
      case 2:
        eval::parseImu(text, "imu.csv");
        break;
      case 3:
        eval::parseScans(text, "scans.jsonl");
        break;
      default:
        eval::parseDatasetInfo(text, "dataset.json");
        break;
    }
  } else if (name == "relations") {
    eval::parseRelations(bytes, "fuzz.relations");
  } else if (name == "bag") {
    // A bag folder whose metadata.yaml is the input, beside one (empty) storage file, bag_0.mcap.
    static const auto folder = [] {
      const auto dir = scratchFile("bag");
      std::filesystem::create_directories(dir);
      writeScratch(dir / "bag_0.mcap", "");
      return dir;
    }();
    writeScratch(folder / "metadata.yaml", bytes);
    eval::readRosbag2(folder);
  } else {
    return false;
  }
  return true;
}

}  // namespace slamprep::fuzz
