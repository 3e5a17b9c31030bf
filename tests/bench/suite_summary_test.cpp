// summary.json as a SuiteSummary: the one to_json and from_json give each other back, a committed
// summary is read and written back to its very bytes (users' scripts read them), and a malformed
// one is refused naming the file and the field.
#include "slamprep/eval/bench/suite_summary.hpp"

#include <gtest/gtest.h>

#include <filesystem>

#include "slamprep/core/atomic_file.hpp"
#include "slamprep/eval/bench/summary.hpp"
#include "slamprep/tests/support/error_of.hpp"
#include "slamprep/tests/support/scratch_dir.hpp"

namespace slamprep::eval {
namespace {

namespace fs = std::filesystem;
using test::errorOf;

const fs::path kResults = fs::path(SLAMPREP_SOURCE_DIR) / "results";

// Two groups of a sweep, one with consistency (a parameter without a NEES for one method, a NEES
// without a parameter for another), numbers that print awkwardly, a missing trial.
SuiteSummary nonTrivialSummary() {
  SuiteSummary s;
  s.suite = "demo";
  s.trials = 5;
  s.missing = {"0005-room-arc-s3"};
  s.metrics = {
      {"calibration/joint/ok", metricStats({1.0, 0.0, 1.0, 1.0, 1.0})},
      {"deskew/odom-linear/mean_m", metricStats({0.1, 0.2, 1e-17, 3.0, 0.30000000000000004})}};
  SummaryGroup a{"worlds/room.yaml",
                 "worlds/scenarios/arc.yaml",
                 {{"lidar.rate_hz", "5"}},
                 3,
                 {{"calibration/joint/ok", metricStats({1.0, 0.0, 1.0})}},
                 {}};
  a.consistency["joint"].params[CalibrationParam::kB] = {3, -0.125, 0.5, 0.51, 2.0 / 3.0, 1.0};
  a.consistency["joint"].params[CalibrationParam::kMountYaw] = {2, 1e-9, 0.0, 1e-9, 0.5, 1.0};
  a.consistency["joint"].nees = NeesConsistency{6.25, 3};
  a.consistency["model"].nees = NeesConsistency{2.5, 1};
  SummaryGroup b = a;
  b.sweep["lidar.rate_hz"] = "10";
  b.trials = 2;
  b.consistency.clear();  // not written: no "consistency" key
  s.groups = {a, b};
  return s;
}

TEST(SuiteSummary, ReadsBackWhatItWrites) {
  const SuiteSummary s = nonTrivialSummary();
  const nlohmann::json written = s;
  EXPECT_FALSE(written["groups"][1].contains("consistency"));
  EXPECT_EQ(written["groups"][0]["consistency"]["calibration/joint/consistency/b/n"].dump(), "3");
  EXPECT_EQ(written["groups"][0]["consistency"]["calibration/model/consistency/nees_n"], 1);
  const SuiteSummary read = parseSuiteSummary(written, "s.json");
  EXPECT_EQ(read, s) << written.dump(2);
  EXPECT_EQ(nlohmann::json(read).dump(2), written.dump(2));
  EXPECT_DOUBLE_EQ(read.groups[0].consistency.at("joint").params.at(CalibrationParam::kB).bias,
                   -0.125);
  EXPECT_EQ(read.metrics.at("deskew/odom-linear/mean_m").n, 5u);
}

TEST(SuiteSummary, CommittedSummariesWriteBackTheirBytes) {
  int files = 0;
  for (const auto& entry : fs::directory_iterator(kResults)) {
    if (!fs::exists(entry.path() / "suite.yaml")) continue;  // twins/ has a summary of its own
    const fs::path file = entry.path() / "summary.json";
    const SuiteSummary s = readSuiteSummary(file);
    EXPECT_EQ(nlohmann::json(s).dump(2) + "\n", readFile(file)) << file;
    EXPECT_FALSE(s.groups.empty()) << file;
    ++files;
  }
  const fs::path baseline = kResults / "regression/baseline.json";  // a summary too
  EXPECT_EQ(nlohmann::json(readSuiteSummary(baseline)).dump(2) + "\n", readFile(baseline));
  EXPECT_GE(files, 6);  // calibration-goal, default, faults, seeds, sweep-calibration, sweep-speed
}

TEST(SuiteSummary, MalformedNamesTheFileAndTheField) {
  const test::ScratchDir scratch("suite_summary");
  const fs::path file = scratch / "summary.json";
  const nlohmann::json good = nonTrivialSummary();
  const auto refusal = [&](const nlohmann::json& bad) {
    writeFileAtomic(file, bad.dump(2));
    return errorOf([&] { readSuiteSummary(file); });
  };
  nlohmann::json bad = good;
  bad["groups"][1]["metrics"]["calibration/joint/ok"].erase("mean");
  EXPECT_EQ(
      refusal(bad),
      file.string() + ": groups[1].metrics.calibration/joint/ok.mean: missing or not a number");
  bad = good;
  bad.erase("suite");
  EXPECT_EQ(refusal(bad), file.string() + ": suite: missing or not a string");
  bad = good;
  bad["groups"][0]["consistency"].erase("calibration/joint/consistency/b/rms");
  EXPECT_EQ(refusal(bad), file.string() +
                              ": groups[0].consistency.calibration/joint/consistency/b/rms: "
                              "missing or not a number");
  bad = good;
  bad["groups"][0]["consistency"]["calibration/joint/consistency/b/median"] = 1.0;
  EXPECT_EQ(refusal(bad), file.string() +
                              ": groups[0].consistency.calibration/joint/consistency/b/median: "
                              "not a consistency statistic");
  bad = good;
  bad["format_version"] = 2;
  EXPECT_EQ(refusal(bad), file.string() + ": format_version: this build reads version 1");
  bad = good;
  bad["missing"][0] = 7;
  EXPECT_EQ(refusal(bad), file.string() + ": missing[0]: not a string");
  EXPECT_EQ(refusal(good), "");
}

}  // namespace
}  // namespace slamprep::eval
