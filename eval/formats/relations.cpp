#include "eval/formats/relations.hpp"

#include <cmath>

#include "core/error.hpp"
#include "eval/formats/text_io.hpp"

namespace slamprep::eval {

std::vector<PoseRelation> parseRelations(std::string_view text, const std::string& file) {
  static constexpr const char* kColumns[8] = {"t1", "t2", "x", "y", "z", "roll", "pitch", "yaw"};
  std::vector<PoseRelation> relations;
  LineCursor cursor(text);
  std::string_view line;
  std::vector<std::string_view> fields;
  double v[8];
  while (cursor.next(line)) {
    line = trim(line);
    if (line.empty() || line.front() == '#') continue;
    const TextLocation where{file, cursor.lineNumber()};
    splitWhitespace(line, fields);
    if (fields.size() != 8)
      throw InputError(where.str(), "expected 8 columns \"t1 t2 x y z roll pitch yaw\", got " +
                                        std::to_string(fields.size()));
    for (int c = 0; c < 8; ++c) v[c] = parseFiniteDouble(fields[c], where, kColumns[c]);
    // The benchmark is planar: a 3D relation cannot be scored against an SE(2) trajectory.
    for (int c = 4; c < 7; ++c)
      if (v[c] != 0.0)
        throw InputError(where.str(), std::string(kColumns[c]) + ": " + std::string(fields[c]) +
                                          " is not 0 (only planar relations are supported)");
    relations.push_back({v[0], v[1], SE2(v[2], v[3], v[7]), where.line});
  }
  return relations;
}

std::vector<PoseRelation> readRelations(const std::string& path) {
  return parseRelations(readTextFile(path), path);
}

}  // namespace slamprep::eval
