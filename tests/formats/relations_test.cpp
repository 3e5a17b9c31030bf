// Relations files (eval/formats/relations.hpp) and the relation metric on the committed
// excerpts: each log's own odometry against its benchmark relations.
#include "slamprep/eval/formats/relations.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "slamprep/core/error.hpp"
#include "slamprep/eval/formats/import.hpp"
#include "slamprep/eval/formats/text_io.hpp"
#include "slamprep/eval/metrics/relation_error.hpp"

namespace slamprep::eval {
namespace {

std::string data(const std::string& name) {
  return std::string(SLAMPREP_SOURCE_DIR) + "/tests/data/" + name;
}

TEST(Relations, ReadsTheBenchmarkFiles) {
  const auto intel = readRelations(data("carmen_intel/intel_first180s.relations"));
  ASSERT_EQ(intel.size(), 87u);  // README: 87 relations
  // Line 1: 976052905.167303 976052911.885496 -0.056990 -0.128430 0 0 0 -1.682210
  EXPECT_EQ(intel[0].t1_s, 976052905.167303);
  EXPECT_EQ(intel[0].t2_s, 976052911.885496);
  EXPECT_EQ(intel[0].T_1_2.x, -0.056990);
  EXPECT_EQ(intel[0].T_1_2.y, -0.128430);
  EXPECT_EQ(intel[0].T_1_2.yaw, -1.682210);
  EXPECT_EQ(intel[0].line, 1u);
  EXPECT_EQ(readRelations(data("carmen_aces/aces_first120s.relations")).size(), 122u);
  EXPECT_EQ(readRelations(data("carmen_fr079/fr079_first60s.relations")).size(), 58u);
}

TEST(Relations, MalformedLinesNameFileLineAndColumn) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"1 2 0.1 0 0 0 0\n", "r.rel:1: expected 8 columns"},
      {"# t1 t2 x y z roll pitch yaw\n1 2 0.1 0 0 0 0 0.1 9\n", "r.rel:2: expected 8 columns"},
      {"1 2 nan 0 0 0 0 0\n", "r.rel:1: x"},
      {"1 2 0 0 0 0 0 inf\n", "r.rel:1: yaw"},
      {"1 x 0 0 0 0 0 0\n", "r.rel:1: t2"},
      {"1 2 0 0 0.5 0 0 0\n", "r.rel:1: z: 0.5 is not 0 (only planar relations"},
      {"\n1 2 0 0 0 0.1 0 0\n", "r.rel:2: roll"},
  };
  for (const auto& [text, expected] : cases) {
    try {
      parseRelations(text, "r.rel");
      ADD_FAILURE() << "accepted: " << text;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  }
  // t2 before t1, repeats and comments are fine.
  EXPECT_EQ(parseRelations("# c\n2 1 0 0 0 0 0 0\n2 1 0 0 0 0 0 0\n", "r").size(), 2u);
}

struct Excerpt {
  std::string log, relations;
  ImportParams params;
  std::size_t relations_count;
};

TEST(Relations, EachExcerptsOdometryScoresASaneFigureAgainstItsRelations) {
  ImportParams trim;
  trim.trim = true;  // fr079: the first scan precedes the first ODOM line
  ImportParams intel;
  intel.reorder_tolerance_s = 1.0;  // Intel's stamps run back by up to 0.88 s here
  // Its ODOM lines leave gaps up to 0.95 s (8 relation stamps beyond the 0.5 s window); the
  // FLASER lines' poses sit at the very stamps the relations name.
  intel.odometry = "laser";
  const std::vector<Excerpt> excerpts = {
      {"carmen_aces/aces_first120s.clf", "carmen_aces/aces_first120s.relations", {}, 122},
      {"carmen_fr079/fr079_first60s.clf", "carmen_fr079/fr079_first60s.relations", trim, 58},
      {"carmen_intel/intel_first180s.clf", "carmen_intel/intel_first180s.relations", intel, 87},
  };
  for (const Excerpt& e : excerpts) {
    SCOPED_TRACE(e.log);
    const ImportResult imported = importCarmen(readTextFile(data(e.log)), e.log, e.params);
    const auto relations = readRelations(data(e.relations));
    const RelationErrorResult r = relationError(imported.dataset.odom_nominal, relations);
    ASSERT_TRUE(r.ok) << r.reason;
    EXPECT_EQ(r.scored.size(), e.relations_count);
    // Raw odometry over relations of a few seconds: centimetres on average (0.02-0.06 m on the
    // whole logs' short relations, docs/score.md), never metres.
    EXPECT_GT(r.all.translation_m.mean, 0.005);
    EXPECT_LT(r.all.translation_m.mean, 0.1);
    EXPECT_LT(r.all.translation_m.max, 0.5);
    EXPECT_LT(r.all.rotation_deg.mean, 5.0);
    // The convention: relation = pose(t1)^-1 pose(t2). Read the other way round, the same
    // odometry is far off, which is how the convention was established.
    std::vector<PoseRelation> inverted = relations;
    for (auto& rel : inverted) rel.T_1_2 = rel.T_1_2.inverse();
    EXPECT_GT(relationError(imported.dataset.odom_nominal, inverted).all.translation_m.mean,
              5 * r.all.translation_m.mean);
  }
}

}  // namespace
}  // namespace slamprep::eval
