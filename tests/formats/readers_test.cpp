// Hardening of every reader against malformed input: truncated files, NaN/Inf, wrong column
// counts, unsorted or duplicate stamps, empty scans, absurd values. Each case must
// raise InputError naming the file and the line or field (never crash, hang or accept).
// The table in docs/export.md lists these cases per reader.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>

#include "slamprep/algo/calibration/interval.hpp"
#include "slamprep/core/atomic_file.hpp"
#include "slamprep/core/dataset.hpp"
#include "slamprep/core/error.hpp"
#include "slamprep/eval/bench/suite.hpp"
#include "slamprep/eval/formats/dataset_io.hpp"
#include "slamprep/sim/drive/config.hpp"
#include "slamprep/sim/drive/scenario.hpp"
#include "slamprep/sim/physics/world.hpp"
#include "slamprep/tests/support/scratch_dir.hpp"
#include "synthetic_dataset.hpp"

namespace slamprep {
namespace {
namespace fs = std::filesystem;

struct Case {
  std::string name;
  std::string text;
  std::vector<std::string> expected;  ///< substrings of the message (file, line or field, what)
};

/// Writes each case to `file`, runs `read`, and checks it throws InputError whose message holds
/// the file name and every expected substring.
void expectRejected(const fs::path& file, const std::vector<Case>& cases,
                    const std::function<void(const fs::path&)>& read) {
  for (const Case& c : cases) {
    writeFileAtomic(file, c.text);
    try {
      read(file);
      ADD_FAILURE() << file.filename() << ": accepted case \"" << c.name << "\"";
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(file.filename().string()), std::string::npos)
          << c.name << ": no file name in: " << what;
      for (const std::string& s : c.expected)
        EXPECT_NE(what.find(s), std::string::npos)
            << c.name << ": expected \"" << s << "\" in: " << what;
    }
  }
}

const char* kWorld =
    "name: t\nstart: {x: 0, y: 0, yaw_deg: 0}\n"
    "walls:\n  - {from: [-5, -5], to: [5, -5], thickness: 0.1, height: 2}\n"
    "cylinders:\n  - {center: [1, 1], radius: 0.5, height: 1}\n";

TEST(ReaderHardening, WorldYaml) {
  const test::ScratchDir scratch("readers");
  const fs::path file = scratch / "world.yaml";
  writeFileAtomic(file, kWorld);
  EXPECT_NO_THROW(sim::loadWorld(file));
  const std::string w = kWorld;
  auto edit = [&](const std::string& from, const std::string& to) {
    std::string s = w;
    s.replace(s.find(from), from.size(), to);
    return s;
  };
  expectRejected(file,
                 {{"truncated", w.substr(0, w.size() - 20), {}},
                  {"NaN radius", edit("radius: 0.5", "radius: .nan"), {"radius"}},
                  {"Inf height", edit("height: 1}", "height: .inf}"), {"height"}},
                  {"negative radius", edit("radius: 0.5", "radius: -0.5"), {"radius"}},
                  {"zero thickness", edit("thickness: 0.1", "thickness: 0"), {"thickness"}},
                  {"wrong column count", edit("[1, 1]", "[1, 1, 1]"), {"center"}},
                  {"wrong type", edit("radius: 0.5", "radius: big"), {"radius"}},
                  {"empty", "", {}}},
                 [](const fs::path& f) { sim::loadWorld(f); });
}

// Was accepted by the reader (simulate's start check happened to refuse it); sizes and
// coordinates are now bounded by 10 km.
TEST(ReaderHardening, WorldYamlAbsurdSize) {
  const test::ScratchDir scratch("readers");
  const fs::path file = scratch / "world.yaml";
  std::string w = kWorld;
  w.replace(w.find("radius: 0.5"), 11, "radius: 1e300");
  expectRejected(file, {{"absurd size", w, {"radius"}}},
                 [](const fs::path& f) { sim::loadWorld(f); });
}

const char* kScenario =
    "name: t\nsegments:\n  - {type: straight, distance_m: 1.0, speed_mps: 0.5}\n"
    "  - {type: stop, duration_s: 0.5}\n";

TEST(ReaderHardening, ScenarioYaml) {
  const test::ScratchDir scratch("readers");
  const fs::path file = scratch / "scenario.yaml";
  writeFileAtomic(file, kScenario);
  EXPECT_NO_THROW(sim::loadScenario(file));
  const std::string s = kScenario;
  auto edit = [&](const std::string& from, const std::string& to) {
    std::string t = s;
    t.replace(t.find(from), from.size(), to);
    return t;
  };
  expectRejected(file,
                 {{"truncated", s.substr(0, s.size() - 12), {}},
                  {"NaN speed", edit("speed_mps: 0.5", "speed_mps: .nan"), {"speed_mps"}},
                  {"Inf distance", edit("distance_m: 1.0", "distance_m: .inf"), {"distance_m"}},
                  {"negative duration", edit("duration_s: 0.5", "duration_s: -1"), {"duration_s"}},
                  {"unknown segment", edit("type: stop", "type: teleport"), {"teleport"}},
                  {"no segments", "name: t\nsegments: []\n", {"segments"}},
                  {"empty", "", {}}},
                 [](const fs::path& f) { sim::loadScenario(f); });
}

TEST(ReaderHardening, ScenarioYamlAbsurdDuration) {
  // Was accepted by the reader; `slamprep simulate --scenario` then simulated 0 s and exited 0.
  const test::ScratchDir scratch("readers");
  const fs::path file = scratch / "scenario.yaml";
  std::string s = kScenario;
  s.replace(s.find("duration_s: 0.5"), 15, "duration_s: 1e300");
  expectRejected(file, {{"absurd duration", s, {"duration_s"}}},
                 [](const fs::path& f) { sim::loadScenario(f); });
}

const char* kSuite =
    "name: t\nworlds: [worlds/room.yaml]\nscenarios: [worlds/scenarios/straight.yaml]\n"
    "seeds: 2\nmode: kinematic\ncalibration_methods: [joint]\ndeskew_methods: [odom-linear]\n";

TEST(ReaderHardening, SuiteYaml) {
  const test::ScratchDir scratch("readers");
  const fs::path file = scratch / "suite.yaml";
  writeFileAtomic(file, kSuite);
  EXPECT_NO_THROW(eval::loadSuite(file));
  const std::string s = kSuite;
  auto edit = [&](const std::string& from, const std::string& to) {
    std::string t = s;
    t.replace(t.find(from), from.size(), to);
    return t;
  };
  expectRejected(file,
                 {{"truncated", s.substr(0, s.find("[joint]") + 3), {}},
                  {"negative seeds", edit("seeds: 2", "seeds: -1"), {"seeds"}},
                  {"zero seeds", edit("seeds: 2", "seeds: 0"), {"seeds"}},
                  {"negative duration", s + "duration_s: -1\n", {"duration_s"}},
                  {"unknown mode", edit("mode: kinematic", "mode: dream"), {"mode"}},
                  {"unknown method", edit("[joint]", "[magic]"), {"magic"}},
                  {"empty", "", {}}},
                 [](const fs::path& f) { eval::loadSuite(f); });
}

TEST(ReaderHardening, SuiteYamlNonFiniteDurationAndAbsurdSeeds) {
  const test::ScratchDir scratch("readers");
  const fs::path file = scratch / "suite.yaml";
  const std::string s = kSuite;
  std::string seeds = s;
  seeds.replace(seeds.find("seeds: 2"), 8, "seeds: 1000000000");
  expectRejected(file,
                 {{"NaN duration", s + "duration_s: .nan\n", {"duration_s"}},
                  {"Inf duration", s + "duration_s: .inf\n", {"duration_s"}},
                  {"absurd seeds (expands to 1e9 trials)", seeds, {"seeds"}}},
                 [](const fs::path& f) { eval::loadSuite(f); });
}

TEST(ReaderHardening, CensiRecords) {
  const std::string good = R"({"T": 0.5, "phi_l": 1.0, "phi_r": 1.2, "sm": [0.05, 0.0, 0.01]})";
  std::istringstream ok(good + "\n");
  EXPECT_EQ(algo::readIntervalRecords(ok, "tuples.json").size(), 1u);
  const std::vector<Case> cases = {
      {"truncated", good.substr(0, 30), {"tuples.json:2"}},
      {"NaN (not JSON)",
       R"({"T": NaN, "phi_l": 1, "phi_r": 1, "sm": [0, 0, 0]})",
       {"tuples.json:2"}},
      {"zero T", R"({"T": 0, "phi_l": 1, "phi_r": 1, "sm": [0, 0, 0]})", {"tuples.json:2", "T"}},
      {"negative T",
       R"({"T": -1, "phi_l": 1, "phi_r": 1, "sm": [0, 0, 0]})",
       {"tuples.json:2", "T"}},
      {"wrong column count",
       R"({"T": 1, "phi_l": 1, "phi_r": 1, "sm": [0, 0]})",
       {"tuples.json:2", "sm"}},
      {"missing key", R"({"T": 1, "phi_l": 1, "sm": [0, 0, 0]})", {"tuples.json:2", "phi_r"}},
      {"wrong type",
       R"({"T": 1, "phi_l": "x", "phi_r": 1, "sm": [0, 0, 0]})",
       {"tuples.json:2", "phi_l"}},
  };
  for (const Case& c : cases) {
    std::istringstream in(good + "\n" + c.text + "\n");
    try {
      algo::readIntervalRecords(in, "tuples.json");
      ADD_FAILURE() << "accepted " << c.name;
    } catch (const InputError& e) {
      for (const std::string& s : c.expected)
        EXPECT_NE(std::string(e.what()).find(s), std::string::npos) << c.name << ": " << e.what();
    }
  }
}

TEST(ReaderHardening, CensiRecordsNumberOverflowIsAnInputError) {
  // nlohmann's out_of_range exception used to escape instead of InputError("tuples.json:1").
  std::istringstream in(R"({"T": 1e999, "phi_l": 1, "phi_r": 1, "sm": [0, 0, 0]})"
                        "\n");
  EXPECT_THROW(algo::readIntervalRecords(in, "tuples.json"), InputError);
}

// A dataset directory with one file replaced.
class DatasetHardening : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = scratch_ / ::testing::UnitTest::GetInstance()->current_test_info()->name();
    test::SyntheticParams p;
    p.duration_s = 0.5;
    p.beams = 8;
    eval::writeDataset(dir_, test::makeSyntheticDataset(p));
  }
  std::string text(const char* file) const { return readFile(dir_ / file); }
  /// Replaces the first `from` in `file` by `to` and expects readDataset to name file + what.
  void expectEditRejected(const char* file, const std::string& from, const std::string& to,
                          const std::vector<std::string>& expected) {
    std::string t = text(file);
    const auto at = t.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    t.replace(at, from.size(), to);
    expectTextRejected(file, t, expected);
  }
  void expectTextRejected(const char* file, const std::string& t,
                          const std::vector<std::string>& expected) {
    const std::string original = text(file);
    writeFileAtomic(dir_ / file, t);
    try {
      eval::readDataset(dir_);
      ADD_FAILURE() << file << ": accepted";
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(file), std::string::npos) << what;
      for (const auto& s : expected)
        EXPECT_NE(what.find(s), std::string::npos) << s << " in " << what;
    }
    writeFileAtomic(dir_ / file, original);
  }
  const test::ScratchDir scratch_{"readers"};
  fs::path dir_;
};

TEST_F(DatasetHardening, TruncatedFiles) {
  for (const char* f : {"dataset.json", "scans.jsonl"}) {
    const std::string t = text(f);
    expectTextRejected(f, t.substr(0, t.size() / 2), {});
  }
  // A TUM or CSV file cut inside its last line loses columns (a cut inside the last number
  // leaves a shorter valid number: no reader can see that).
  const std::string gt = text("groundtruth.tum");
  expectTextRejected("groundtruth.tum", gt.substr(0, gt.rfind(' ')), {"column"});
  const std::string enc = text("encoders.csv");
  expectTextRejected("encoders.csv", enc.substr(0, enc.rfind(',') + 1), {"ticks_right"});
}

TEST_F(DatasetHardening, NanInfAndWrongColumns) {
  expectEditRejected("encoders.csv", "\n0.01,", "\nnan,", {"encoders.csv:3"});
  expectEditRejected("imu.csv", "\n0.005,", "\n0.005,inf,", {"imu.csv:3"});
  expectEditRejected("imu.csv", "\n0.005,", "\n0.005,1,", {"imu.csv:3"});  // 5 columns
  expectEditRejected("groundtruth.tum", "\n0.005 ", "\n0.005 1 ", {"groundtruth.tum:3"});
  expectEditRejected("scans.jsonl", "\"stamp_s\":0.1,", "\"stamp_s\":1e999,", {"scans.jsonl:2"});
}

TEST_F(DatasetHardening, UnsortedAndDuplicateStamps) {
  expectEditRejected("encoders.csv", "\n0.01,", "\n0,", {"encoders.csv:3", "duplicate"});
  expectEditRejected("odom_nominal.tum", "\n0.01 ", "\n-1 ", {"odom_nominal.tum:3"});
  expectEditRejected("scans.jsonl", "\"stamp_s\":0.1,", "\"stamp_s\":0,", {"scans.jsonl:2"});
}

TEST_F(DatasetHardening, AbsurdValues) {
  expectEditRejected("dataset.json", "\"r_L\": 0.1,", "\"r_L\": -0.1,", {"nominal.r_L"});
  expectEditRejected("dataset.json", "\"ticks_per_revolution\": 4096",
                     "\"ticks_per_revolution\": 0", {"ticks_per_revolution"});
  expectEditRejected("scans.jsonl", "\"nrays\":8", "\"nrays\":1000000000", {"scans.jsonl:1"});
}

// The three gaps below were accepted by readDataset before the reader hardening (docs/export.md).
TEST_F(DatasetHardening, NegativeRangeMinIsRejected) {
  expectEditRejected("scans.jsonl", "\"range_min\":0.05", "\"range_min\":-1", {"scans.jsonl:1"});
}

TEST_F(DatasetHardening, EmptyScanIsRejected) {
  // writeDataset published a scan with no beams and readDataset read it back; now the writer
  // refuses it (and the reader would too).
  test::SyntheticParams p;
  p.duration_s = 0.5;
  p.beams = 8;
  Dataset d = test::makeSyntheticDataset(p);
  d.scans[2].scan.ranges_m.clear();
  EXPECT_THROW(
      {
        eval::writeDataset(dir_, d);
        eval::readDataset(dir_);
      },
      InputError);
}

TEST_F(DatasetHardening, ScansOutsideTheOdometryAreRejected) {
  // Odometry (encoders, odom_nominal) ends at 0.5 s; a scan stamped 100 s was accepted.
  std::string t = text("scans.jsonl");
  const std::string last = t.substr(t.rfind('\n', t.size() - 2) + 1);
  std::string moved = last;
  const auto at = moved.find("\"stamp_s\":");
  moved.replace(at, moved.find(',', at) - at, "\"stamp_s\":100");
  expectTextRejected("scans.jsonl", t + moved, {"scans.jsonl:6"});
}

TEST(ReaderHardening, SimulatorConfigAbsurdLidar) {
  for (const char* bad : {"lidar.beams_per_revolution=0", "lidar.range_max_m=-1",
                          "lidar.rate_hz=nan", "wheels.radius_left_m=-0.1"}) {
    sim::SimConfig c;
    try {
      sim::applyOverride(c, bad);
      sim::validate(c, "--set");
      ADD_FAILURE() << "accepted " << bad;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(std::string(bad).substr(0, std::string(bad).find('='))),
                std::string::npos)
          << e.what();
    }
  }
}

TEST(ReaderHardening, SimulatorConfigRefusesAbsurdBeamCounts) {
  // 1e9 beams per revolution = 1e10 ray casts per simulated second: an effective hang.
  sim::SimConfig c;
  EXPECT_THROW(
      {
        sim::applyOverride(c, "lidar.beams_per_revolution=1000000000");
        sim::validate(c, "--set");
      },
      InputError);
}

}  // namespace
}  // namespace slamprep
