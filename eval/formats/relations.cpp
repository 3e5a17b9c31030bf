#include "slamprep/eval/formats/relations.hpp"

#include <cmath>

#include "slamprep/core/error.hpp"
#include "slamprep/eval/formats/text_io.hpp"

namespace slamprep::eval {

std::vector<PoseRelation> parseRelations(std::string_view text, const std::string& file) {
  static constexpr std::array<const char*, 8> kColumns = {"t1", "t2",   "x",     "y",
                                                          "z",  "roll", "pitch", "yaw"};
  std::vector<PoseRelation> relations;
  forEachNumberRow(
      text, file, kColumns, [&](const auto& v, const TextLocation& where, auto& fields) {
        // The benchmark is planar: a 3D relation cannot be scored against an SE(2) trajectory.
        for (int c = 4; c < 7; ++c)
          if (v[c] != 0.0)
            throw InputError(where.str(), std::string(kColumns[c]) + ": " + std::string(fields[c]) +
                                              " is not 0 (only planar relations are supported)");
        relations.push_back({v[0], v[1], SE2(v[2], v[3], v[7]), where.line});
      });
  return relations;
}

std::vector<PoseRelation> readRelations(const std::string& path) {
  return parseRelations(readTextFile(path), path);
}

}  // namespace slamprep::eval
