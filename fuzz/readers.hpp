#pragma once
// Every reader behind one call, shared by the libFuzzer targets (fuzz/fuzz_<reader>.cpp) and the
// ctest replay of the corpus and regressions (tests/formats/fuzz_regression_test.cpp). A reader
// passes an input when it returns or throws InputError.

#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "slamprep/algo/calibration/calibration_json.hpp"
#include "slamprep/algo/calibration/interval.hpp"
#include "slamprep/eval/bench/suite.hpp"
#include "slamprep/fuzz/format_readers.hpp"
#include "slamprep/sim/drive/scenario.hpp"
#include "slamprep/sim/physics/world.hpp"

namespace slamprep::fuzz {

inline const std::vector<std::string>& readerNames() {
  static const std::vector<std::string> names = {"mcap",        "carmen", "dataset", "world",
                                                 "scenario",    "suite",  "censi",   "relations",
                                                 "calibration", "bag"};
  return names;
}

/// Feeds `bytes` to reader `name`. Throws whatever the reader throws.
inline void readAs(const std::string& name, std::string_view bytes) {
  if (readFormatAs(name, bytes)) return;
  if (name == "world") {
    static const auto file = scratchFile("world.yaml");
    writeScratch(file, bytes);
    sim::loadWorld(file);
  } else if (name == "scenario") {
    // Includes resolve next to the (non-existent) source file, inside the scratch directory.
    static const auto source = scratchFile("scenario.yaml");
    sim::parseScenario(std::string(bytes), source);
  } else if (name == "suite") {
    static const auto file = scratchFile("suite.yaml");
    writeScratch(file, bytes);
    eval::loadSuite(file);
  } else if (name == "censi") {
    std::istringstream in{std::string(bytes)};
    algo::readIntervalRecords(in, "tuples.json");
  } else if (name == "calibration") {
    algo::parseCalibrationJson(bytes, "calibration.json");
  }
}

}  // namespace slamprep::fuzz
