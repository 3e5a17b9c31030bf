// End-to-end: `slamprep simulate` a short arc, then `slamprep deskew` and `slamprep match` on it:
// files written, JSON keys, exit codes and messages for bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "slamprep/tests/support/cli_run.hpp"
#include "slamprep/tests/support/scratch_dir.hpp"

namespace {

namespace fs = std::filesystem;

using slamprep::test::CliRun;
using slamprep::test::slurp;

class DeskewCommand : public ::testing::Test {
 protected:
  // One folder per process: ctest runs these tests in parallel processes, each with its own
  // SetUpTestSuite, and a shared folder let one process wipe another's dataset.
  static inline std::optional<slamprep::test::ScratchDir> scratch_;
  static const fs::path& dir() { return scratch_->path(); }
  static void SetUpTestSuite() {
    scratch_.emplace("deskew_cli");
    // 3 s of the arc (ramp included), kinematic: fast and exact.
    const CliRun r = cli({"simulate", "--scenario", "worlds/scenarios/arc.yaml", "--duration", "3",
                          "--mode", "kinematic", "--quiet", "--out", data()});
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  static void TearDownTestSuite() { scratch_.reset(); }

  static CliRun cli(const std::vector<std::string>& args) {
    return slamprep::test::runSlamprep(args, dir());
  }
  static std::string data() { return (dir() / "data").string(); }
  // One method on `dataset` with `flags` added: the mean error of its --json, stdout in `out`.
  static double deskewMean(const std::string& dataset, const std::string& method,
                           const std::vector<std::string>& flags, std::string* out) {
    const fs::path json = dir() / "mean.json";
    std::vector<std::string> args = {"deskew",  dataset,  "--method",   method,
                                     "--force", "--json", json.string()};
    args.insert(args.end(), flags.begin(), flags.end());
    const CliRun r = cli(args);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    *out = r.out;
    return nlohmann::json::parse(slurp(json))[0]["mean_m"].get<double>();
  }
};

TEST_F(DeskewCommand, AllMethodsWriteScansAndJson) {
  const fs::path json = dir() / "deskew.json";
  const fs::path out = dir() / "deskewed";
  const CliRun r = cli({"deskew", data(), "--method", "all", "--force", "--json", json.string(),
                        "--out", out.string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(slurp(json));
  ASSERT_EQ(j.size(), 8u);  // every method: the dataset has truth, so the oracle too
  for (const auto& m : j) {
    for (const char* key : {"method", "mean_m", "rms_m", "p95_m", "max_m", "beams", "seconds"})
      EXPECT_TRUE(m.contains(key)) << key;
    EXPECT_TRUE(fs::exists(out / ("deskewed_" + m["method"].get<std::string>() + ".jsonl")));
    EXPECT_FALSE(
        fs::exists(dir() / "data" / ("deskewed_" + m["method"].get<std::string>() + ".jsonl")));
    EXPECT_EQ(m["refused"], 0);
    EXPECT_EQ(m["ok"], m["scans"]);
    EXPECT_TRUE(m["refused_by_reason"].is_object() && m["refused_by_reason"].empty());
    EXPECT_TRUE(m["refusals"].is_array() && m["refusals"].empty());
    // Nothing refused: the figure over every scan is the one over the de-skewed scans.
    EXPECT_EQ(m["fallback_mean_m"], m["mean_m"]);
    EXPECT_EQ(m["fallback_p95_m"], m["p95_m"]);
  }
  EXPECT_EQ(j[0]["method"], "none");
  EXPECT_LT(j[1]["mean_m"].get<double>(), 1e-9);  // oracle
  // The oracle's points are the truth: repacked the same way they give the same grid.
  EXPECT_LT(j[1]["repacked_mean_m"].get<double>(), 1e-9);
  EXPECT_EQ(j[1]["repacked_lost_beams"], 0);
  for (const auto& m : j)
    for (const char* key : {"repacked_mean_m", "repacked_p95_m", "repacked_lost_beams"})
      EXPECT_TRUE(m.contains(key)) << key;
  EXPECT_GT(j[0]["mean_m"].get<double>(), 0.01);  // none: really distorted
  // Same line count as scans.jsonl; de-skewed lines carry time_increment 0.
  auto lines = [](const fs::path& f) {
    std::ifstream in(f);
    std::string line;
    std::vector<std::string> out;
    while (std::getline(in, line))
      if (!line.empty()) out.push_back(line);
    return out;
  };
  const auto scans = lines(dir() / "data" / "scans.jsonl");
  const auto deskewed = lines(out / "deskewed_odom-linear.jsonl");
  ASSERT_EQ(scans.size(), deskewed.size());
  EXPECT_EQ(nlohmann::json::parse(deskewed[3])["time_increment"], 0.0);
  // ... and the exact corrected points, one per measured beam, for the CSM export's theta.
  EXPECT_EQ(nlohmann::json::parse(deskewed[3])["p_ref"].size(),
            nlohmann::json::parse(scans[3])["nrays"].get<std::size_t>());
}

TEST_F(DeskewCommand, MatchWritesOneLinePerPair) {
  const CliRun r = cli({"match", data(), "--force", "--out", (dir() / "matches.jsonl").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::ifstream in(dir() / "matches.jsonl");
  std::string line;
  int n = 0;
  while (std::getline(in, line)) {
    const auto m = nlohmann::json::parse(line);
    EXPECT_EQ(m["T_ref_cur"].size(), 3u);
    EXPECT_EQ(m["covariance"].size(), 9u);
    EXPECT_TRUE(m["converged"].get<bool>());
    ++n;
  }
  EXPECT_EQ(n, 29);  // 30 scans in 3 s at 10 Hz
}

TEST_F(DeskewCommand, BadInputNamesTheProblem) {
  CliRun r = cli({"deskew", (dir() / "missing").string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("missing"), std::string::npos) << r.err;
  std::ofstream(dir() / "cal.json")
      << R"([{"method": "model", "ok": true, "r_L": 0, "r_R": 0.1, "b": 0.5}])";
  r = cli({"deskew", data(), "--calibration", (dir() / "cal.json").string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("r_L"), std::string::npos) << r.err;
  std::ofstream(dir() / "cal2.json")
      << R"([{"method": "x", "ok": true, "r_L": 0.1, "r_R": 0.1, "b": 0.5}])";
  r = cli({"deskew", data(), "--calibration", (dir() / "cal2.json").string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("[0].method"), std::string::npos) << r.err;
  r = cli({"deskew", data(), "--method", "linear"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("did you mean 'odom-linear'?"), std::string::npos) << r.err;
}

// A wrong stamp convention pushes the first scans' beams before the odometry starts: those are
// refused, listed with their reason, counted in `ok`, and the mean covers the others.
TEST_F(DeskewCommand, EveryRefusalIsListedAndCounted) {
  const fs::path json = dir() / "refusals.json";
  const CliRun r = cli({"deskew", data(), "--method", "odom-linear", "--stamp-is-last-beam",
                        "--force", "--json", json.string()});
  const auto m = nlohmann::json::parse(slurp(json)).at(0);
  const int refused = m["refused"], scans = m["scans"];
  ASSERT_GT(refused, 0) << r.out;
  ASSERT_LT(refused, scans) << r.out;
  EXPECT_EQ(r.exit_code, 0) << r.err;  // not every scan refused, no --strict
  EXPECT_EQ(m["ok"], scans - refused);
  EXPECT_EQ(m["refused_by_reason"], nlohmann::json({{"not-bracketed", refused}}));
  ASSERT_EQ(m["refusals"].size(), static_cast<std::size_t>(refused));
  for (const auto& x : m["refusals"]) {
    EXPECT_EQ(x["method"], "odom-linear");
    EXPECT_EQ(x["reason"], "not-bracketed");
    EXPECT_NE(x["detail"].get<std::string>().find("does not bracket"), std::string::npos);
  }
  EXPECT_EQ(m["refusals"][0]["scan"], 0);
  const std::string counted = "ok " + std::to_string(scans - refused) + " of " +
                              std::to_string(scans) + " scans; refused: not-bracketed " +
                              std::to_string(refused);
  EXPECT_NE(r.out.find(counted), std::string::npos) << r.out;
  EXPECT_EQ(cli({"deskew", data(), "--method", "odom-linear", "--stamp-is-last-beam", "--strict"})
                .exit_code,
            3);
}

// fallback_* count a refused scan as measured, as `match` keeps it: odom-linear's mean over every
// scan is the beam-weighted mix of its own mean over the scans it kept and none's over the scans
// it refused (the first ones, stamped before the odometry starts).
TEST_F(DeskewCommand, FallbackCountsRefusedScansAsMeasured) {
  auto run = [&](const std::vector<std::string>& extra, std::string* out) {
    const fs::path json = dir() / "fallback.json";
    std::vector<std::string> args = {"deskew",  data(),   "--stamp-is-last-beam",
                                     "--force", "--json", json.string()};
    args.insert(args.end(), extra.begin(), extra.end());
    const CliRun r = cli(args);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    if (out) *out = r.out;
    return nlohmann::json::parse(slurp(json)).at(0);
  };
  std::string printed;
  const auto linear = run({"--method", "odom-linear"}, &printed);
  const int refused = linear["refused"];
  ASSERT_GT(refused, 0);
  for (int k = 0; k < refused; ++k) ASSERT_EQ(linear["refusals"][k]["scan"], k);
  // none over the refused scans only: a window ending between the last refused and the next.
  std::vector<double> stamps;
  std::ifstream in(dir() / "data" / "scans.jsonl");
  for (std::string line; std::getline(in, line);)
    if (!line.empty()) stamps.push_back(nlohmann::json::parse(line)["stamp_s"].get<double>());
  ASSERT_LT(static_cast<std::size_t>(refused), stamps.size());
  const double end = 0.5 * (stamps[refused - 1] + stamps[refused]);
  const auto none = run({"--method", "none", "--window", "0", std::to_string(end)}, nullptr);
  const double n_kept = linear["beams"], n_refused = none["beams"];
  ASSERT_GT(n_refused, 0.0);
  const double mix =
      (linear["mean_m"].get<double>() * n_kept + none["mean_m"].get<double>() * n_refused) /
      (n_kept + n_refused);
  EXPECT_NEAR(linear["fallback_mean_m"].get<double>(), mix, 1e-12);
  EXPECT_GT(std::abs(mix - linear["mean_m"].get<double>()), 1e-4);  // the refused scans count
  EXPECT_GE(linear["fallback_p95_m"].get<double>(), 0.0);
  EXPECT_NE(printed.find("all scans, the refused as measured: mean"), std::string::npos) << printed;
}

// Scans stamped 0.1 s late (clock_offset) on a drive whose turn rate keeps changing, which is
// what shows a delay: --sync auto measures it (0.100-0.101 s, seeds 1-3; 0.050-0.057 s while the
// poses of scans matched as measured were read at their first beam, not mid-sweep) and
// odom-linear, reading the wheels on the scans' clock, errs 2.57 mm against 11.10 mm as logged.
TEST_F(DeskewCommand, SyncAutoMovesTheWheelsOntoTheScansClock) {
  const std::string late = (dir() / "late").string();
  ASSERT_EQ(
      cli({"simulate", "--scenario", "worlds/scenarios/random_smooth.yaml", "--duration", "30",
           "--mode", "kinematic", "--quiet", "--seed", "1", "--set", "faults.enable=clock_offset",
           "--set", "faults.clock_offset.offset_s=0.1", "--out", late})
          .exit_code,
      0);
  std::string out_auto, out_none;
  const double synced = deskewMean(late, "odom-linear", {"--sync", "auto"}, &out_auto);
  const double logged = deskewMean(late, "odom-linear", {"--sync", "none"}, &out_none);
  EXPECT_LT(synced, 0.5 * logged);
  const std::size_t at = out_auto.find("--sync auto: the scans lagged the wheels by ");
  ASSERT_NE(at, std::string::npos) << out_auto;
  EXPECT_NEAR(std::stod(out_auto.substr(at + 44)), 0.1, 0.015);
  EXPECT_EQ(out_none.find("--sync auto"), std::string::npos);
}

// 1 ms of stamp jitter on every stream: odom-icp's error on the 3 s arc (seeds 1, 2, 4, 5) was
// 4.4-5.0 mm with the stamps as logged and 1.0-1.2 mm with them back on their grids (a ratio of
// 0.22-0.25); the clean dataset's stamps are left alone and nothing is printed for them.
TEST_F(DeskewCommand, JitteredStampsGoBackOnTheirGrid) {
  const std::string jittered = (dir() / "jittered").string();
  ASSERT_EQ(cli({"simulate", "--scenario", "worlds/scenarios/arc.yaml", "--duration", "3", "--mode",
                 "kinematic", "--quiet", "--seed", "1", "--set", "faults.enable=stamp_jitter",
                 "--out", jittered})
                .exit_code,
            0);
  std::string out_auto, out_raw;
  const double regular = deskewMean(jittered, "odom-icp", {"--stamps", "auto"}, &out_auto);
  const double raw = deskewMean(jittered, "odom-icp", {"--stamps", "raw"}, &out_raw);
  EXPECT_LT(regular, 0.4 * raw);
  EXPECT_LT(regular, 1.5e-3);
  EXPECT_NE(out_auto.find("stamps: scans put on their"), std::string::npos) << out_auto;
  EXPECT_EQ(out_raw.find("stamps:"), std::string::npos);
  EXPECT_EQ(cli({"deskew", data(), "--method", "odom-icp"}).out.find("stamps:"), std::string::npos);
}

}  // namespace
