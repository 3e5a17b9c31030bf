#pragma once
// Relations files of the SLAM benchmark of Kümmerle et al. 2009 (docs/score.md): one relation
// per line, "t1 t2 x y z roll pitch yaw" (s, m, rad), the relative pose of the robot at t2 seen
// from the robot at t1; '#' comments.

#include <string>
#include <string_view>
#include <vector>

#include "slamprep/core/pose_relation.hpp"

namespace slamprep::eval {

/// Parses a relations file; `file` names it in errors. Rejects, naming file, line and column:
/// a column count other than 8, non-numbers, NaN/Inf, and non-planar relations (z, roll or pitch
/// not 0). t2 may precede t1 and relations may repeat.
std::vector<PoseRelation> parseRelations(std::string_view text, const std::string& file);

std::vector<PoseRelation> readRelations(const std::string& path);

}  // namespace slamprep::eval
