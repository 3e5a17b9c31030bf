#include "slamprep/eval/formats/dataset_json.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "slamprep/core/error.hpp"

namespace slamprep::eval {
namespace {

DatasetInfo sampleInfo() {
  DatasetInfo info;
  info.world = "w.yaml";
  info.scenario = "s.yaml";
  info.seed = 18446744073709551615ULL;
  info.true_geometry = DiffDriveParams{0.1003, 0.0998, 0.5123};
  info.nominal_geometry = {0.1, 0.1, 0.5};
  info.T_base_lidar = SE2(0.1, -0.02, 0.03);
  info.ticks_per_revolution = 2048;
  info.config = {{"k", 1.5}, {"nested", {{"list", {1, 2, 3}}}}};
  return info;
}

TEST(DatasetJson, WritesTheDocumentedKeys) {
  const nlohmann::json j = nlohmann::json::parse(formatDatasetInfo(sampleInfo(), "d.json"));
  EXPECT_EQ(j["format_version"], 1);
  EXPECT_EQ(j["seed"].get<std::uint64_t>(), 18446744073709551615ULL);
  EXPECT_EQ(j["true"]["r_L"], 0.1003);
  EXPECT_EQ(j["nominal"]["b"], 0.5);
  EXPECT_EQ(j["lidar_mount"]["yaw"], 0.03);
  EXPECT_EQ(j["ticks_per_revolution"], 2048);
  EXPECT_EQ(j["config"]["nested"]["list"][2], 3);
}

TEST(DatasetJson, RealLogsHaveNoTrueGeometry) {
  DatasetInfo info = sampleInfo();
  info.true_geometry.reset();
  const std::string text = formatDatasetInfo(info, "d.json");
  EXPECT_EQ(text.find("\"true\""), std::string::npos);
  EXPECT_FALSE(parseDatasetInfo(text, "d.json").true_geometry.has_value());
}

// A simulation told a wrong mount keeps the true one beside it; one told right writes none.
TEST(DatasetJson, KeepsATrueMountBesideAToldOne) {
  DatasetInfo info = sampleInfo();
  EXPECT_EQ(formatDatasetInfo(info, "d.json").find("true_lidar_mount"), std::string::npos);
  info.true_T_base_lidar = SE2(0.15, -0.02, 0.01);
  const DatasetInfo back = parseDatasetInfo(formatDatasetInfo(info, "d.json"), "d.json");
  EXPECT_EQ(back.T_base_lidar.x, 0.1);
  ASSERT_TRUE(back.true_T_base_lidar.has_value());
  EXPECT_EQ(back.trueMount().x, 0.15);
  EXPECT_EQ(back.trueMount().yaw, 0.01);
  info.true_T_base_lidar->y = std::nan("");
  EXPECT_THROW(formatDatasetInfo(info, "d.json"), InputError);
}

void expectError(const nlohmann::json& j, const std::string& expected) {
  try {
    parseDatasetInfo(j.dump(), "d.json");
    ADD_FAILURE() << "accepted: " << j.dump();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(expected), std::string::npos)
        << e.what() << "\nexpected: " << expected;
  }
}

TEST(DatasetJson, RejectsMissingKeysWrongTypesAndBadValues) {
  const nlohmann::json good = nlohmann::json::parse(formatDatasetInfo(sampleInfo(), "d.json"));
  for (const char* key : {"format_version", "world", "scenario", "seed", "nominal", "lidar_mount",
                          "ticks_per_revolution", "config"}) {
    nlohmann::json j = good;
    j.erase(key);
    expectError(j, std::string("d.json: ") + key + ": missing required key");
  }
  auto with = [&](const nlohmann::json::json_pointer& p, const nlohmann::json& v) {
    nlohmann::json j = good;
    j[p] = v;
    return j;
  };
  using P = nlohmann::json::json_pointer;
  expectError(with(P("/format_version"), 2), "d.json: format_version: unsupported version 2");
  expectError(with(P("/nominal/r_L"), 0.0), "d.json: nominal.r_L: must be > 0");
  expectError(with(P("/true/b"), -0.5), "d.json: true.b: must be > 0");
  expectError(with(P("/true/r_R"), "0.1"), "d.json: true.r_R: expected a number");
  expectError(with(P("/ticks_per_revolution"), 0),
              "d.json: ticks_per_revolution: must be a positive");
  expectError(with(P("/ticks_per_revolution"), 4096.5),
              "d.json: ticks_per_revolution: expected an integer");
  expectError(with(P("/seed"), -1), "d.json: seed: expected a non-negative integer");
  expectError(with(P("/lidar_mount/yaw"), nullptr), "d.json: lidar_mount.yaw: expected a number");
  expectError(with(P("/config"), 3), "d.json: config: expected an object");
  expectError(with(P("/world"), 3), "d.json: world: expected a string");
  nlohmann::json j = good;
  j["nominal"].erase("b");
  expectError(j, "d.json: nominal.b: missing required key");
}

TEST(DatasetJson, SyntaxErrorsNameTheLine) {
  try {
    parseDatasetInfo("{\n  \"a\": 1,\n  \"b\": ]\n}", "d.json");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("d.json:3: bad JSON"), std::string::npos) << e.what();
  }
  EXPECT_THROW(parseDatasetInfo("[]", "d.json"), InputError);
  EXPECT_THROW(parseDatasetInfo("", "d.json"), InputError);
}

// A config nested 200 000 deep crashed every reader (SIGSEGV), and 10 000
// deep was written back as 200 MB; a repeated key kept one value silently.
TEST(DatasetJson, DeepNestingAndRepeatedKeysAreRefusedNamingTheLine) {
  const std::string good = formatDatasetInfo(sampleInfo(), "d.json");
  for (int depth : {65, 10000, 200000}) {
    std::string deep = good;
    deep.replace(deep.find("\"config\": {") + 11, 0,
                 "\"deep\": " + std::string(depth, '[') + std::string(depth, ']') + ",");
    try {
      parseDatasetInfo(deep, "d.json");
      ADD_FAILURE() << "accepted depth " << depth;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("JSON nested deeper than 64 levels"), std::string::npos)
          << e.what();
    }
  }
  std::string twice = good;
  twice.replace(twice.find("\"seed\""), 0, "\"seed\": 5,\n");
  try {
    parseDatasetInfo(twice, "d.json");
    FAIL() << "accepted a repeated key";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("key \"seed\" appears twice in one object"),
              std::string::npos)
        << e.what();
  }
}

TEST(DatasetJson, WriterRefusesInvalidGeometry) {
  DatasetInfo info = sampleInfo();
  info.nominal_geometry.wheel_base_m = 0.0;
  EXPECT_THROW(formatDatasetInfo(info, "d.json"), InputError);
  info = sampleInfo();
  info.ticks_per_revolution = -1;
  EXPECT_THROW(formatDatasetInfo(info, "d.json"), InputError);
}

}  // namespace
}  // namespace slamprep::eval
