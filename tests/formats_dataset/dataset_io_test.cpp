#include "slamprep/eval/formats/dataset_io.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <random>

#include "slamprep/core/dataset.hpp"
#include "slamprep/core/error.hpp"
#include "slamprep/eval/formats/scan_jsonl.hpp"
#include "slamprep/eval/formats/text_io.hpp"
#include "slamprep/tests/formats_dataset/dataset_compare.hpp"
#include "slamprep/tests/formats_dataset/synthetic_dataset.hpp"
#include "slamprep/tests/support/scratch_dir.hpp"

namespace slamprep {
namespace {

namespace fs = std::filesystem;
using synthetic::makeSyntheticDataset;
using synthetic::SyntheticDatasetParams;

class DatasetIo : public ::testing::Test {
 protected:
  // Only the target's own directory (and none of its .partial-/.old- siblings) may exist.
  std::vector<std::string> entries() const {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(root_)) names.push_back(e.path().filename());
    std::sort(names.begin(), names.end());
    return names;
  }

  const test::ScratchDir scratch_{"dataset_io"};
  const fs::path root_ = scratch_.path();
};

std::string slurp(const fs::path& p) {
  return eval::readTextFile(p);
}
void spit(const fs::path& p, const std::string& text) {
  std::ofstream(p, std::ios::binary) << text;
}

// Replaces 1-based line `n` of a file.
void replaceLine(const fs::path& p, std::size_t n, const std::string& line) {
  std::istringstream in(slurp(p));
  std::string out, current;
  for (std::size_t k = 1; std::getline(in, current); ++k) out += (k == n ? line : current) + "\n";
  spit(p, out);
}

std::string lineOf(const fs::path& p, std::size_t n) {
  std::istringstream in(slurp(p));
  std::string current;
  for (std::size_t k = 1; std::getline(in, current); ++k)
    if (k == n) return current;
  return {};
}

TEST_F(DatasetIo, RoundTripIsBitExactWithTruth) {
  const Dataset d = makeSyntheticDataset({});
  ASSERT_TRUE(d.hasTruth());
  eval::writeDataset(root_ / "run", d);
  const Dataset back = eval::readDataset(root_ / "run");
  EXPECT_TRUE(back.hasTruth());
  synthetic::expectSameDataset(d, back);
  EXPECT_EQ(entries(), std::vector<std::string>{"run"});
  // Writing what was read gives the same bytes (determinism of the writer).
  eval::writeDataset(root_ / "again", back);
  for (const char* f : {"dataset.json", "groundtruth.tum", "odom_nominal.tum", "encoders.csv",
                        "imu.csv", "scans.jsonl"})
    EXPECT_EQ(slurp(root_ / "run" / f), slurp(root_ / "again" / f)) << f;
  // Optional, and written only when there is a logged odometry beside the encoders.
  EXPECT_FALSE(std::filesystem::exists(root_ / "run" / eval::kOdometryLoggedTum));
}

TEST_F(DatasetIo, RoundTripIsBitExactWithoutTruth) {
  SyntheticDatasetParams p;
  p.with_truth = false;
  p.logged_odometry = true;
  p.varying_beams = true;
  const Dataset d = makeSyntheticDataset(p);
  ASSERT_FALSE(d.odometry_logged.empty());
  ASSERT_NE(d.scans[0].scan.size(), d.scans[1].scan.size());
  eval::writeDataset(root_ / "real/", d);  // trailing slash names the same directory
  const Dataset back = eval::readDataset(root_ / "real");
  EXPECT_FALSE(back.hasTruth());
  EXPECT_TRUE(back.groundtruth.empty());
  synthetic::expectSameDataset(d, back);
  eval::writeDataset(root_ / "real_again", back);
  EXPECT_EQ(slurp(root_ / "real" / eval::kOdometryLoggedTum),
            slurp(root_ / "real_again" / eval::kOdometryLoggedTum));
  EXPECT_EQ(slurp(root_ / "real/scans.jsonl").find("p_ref_true"), std::string::npos);
  EXPECT_EQ(slurp(root_ / "real/scans.jsonl").find("true_pose"), std::string::npos);
}

TEST_F(DatasetIo, EmptyDatasetRoundTrips) {
  eval::writeDataset(root_ / "empty", Dataset{});
  synthetic::expectSameDataset(Dataset{}, eval::readDataset(root_ / "empty"));
}

TEST_F(DatasetIo, RewritingReplacesTheOldDatasetCompletely) {
  SyntheticDatasetParams p;
  p.duration_s = 0.5;
  eval::writeDataset(root_ / "run", makeSyntheticDataset(p));
  spit(root_ / "run" / "stale.txt", "from an older writer");
  p.seed = 99;
  p.with_truth = false;
  const Dataset second = makeSyntheticDataset(p);
  eval::writeDataset(root_ / "run", second);
  synthetic::expectSameDataset(second, eval::readDataset(root_ / "run"));
  EXPECT_FALSE(fs::exists(root_ / "run" / "stale.txt"));
  EXPECT_EQ(entries(), std::vector<std::string>{"run"});
}

TEST_F(DatasetIo, FailedWriteLeavesNoPartialDirectoryAndKeepsTheOldDataset) {
  SyntheticDatasetParams p;
  p.duration_s = 0.5;
  const Dataset old = makeSyntheticDataset(p);
  eval::writeDataset(root_ / "run", old);
  Dataset bad = makeSyntheticDataset(p);
  bad.scans.back().p_ref_true.pop_back();  // scans.jsonl is written last: the others exist then
  try {
    eval::writeDataset(root_ / "run", bad);
    FAIL() << "wrote an inconsistent dataset";
  } catch (const InputError& e) {
    const std::string expected =
        (root_ / "run" / "scans.jsonl").string() + ":5: p_ref_true: has 719 entries for 720";
    EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
  }
  EXPECT_EQ(entries(), std::vector<std::string>{"run"});
  synthetic::expectSameDataset(old, eval::readDataset(root_ / "run"));
  // A fresh target: nothing at all remains.
  EXPECT_THROW(eval::writeDataset(root_ / "fresh", bad), InputError);
  EXPECT_EQ(entries(), std::vector<std::string>{"run"});
}

TEST_F(DatasetIo, RefusesToReplaceSomethingThatIsNotADataset) {
  fs::create_directories(root_ / "home");
  spit(root_ / "home" / "thesis.tex", "precious");
  spit(root_ / "file", "a file");
  SyntheticDatasetParams p;
  p.duration_s = 0.2;
  EXPECT_THROW(eval::writeDataset(root_ / "home", makeSyntheticDataset(p)), InputError);
  EXPECT_THROW(eval::writeDataset(root_ / "file", makeSyntheticDataset(p)), InputError);
  EXPECT_EQ(slurp(root_ / "home" / "thesis.tex"), "precious");
  EXPECT_EQ(slurp(root_ / "file"), "a file");
  EXPECT_EQ(entries(), (std::vector<std::string>{"file", "home"}));
}

TEST_F(DatasetIo, StalePartialDirectoryFromACrashIsNotADataset) {
  // A crash leaves only `<dir>.partial-<pid>`; `dir` itself never appears half written.
  fs::create_directories(eval::partialDirectory(root_ / "run"));
  EXPECT_THROW(eval::readDataset(root_ / "run"), InputError);
  SyntheticDatasetParams p;
  p.duration_s = 0.2;
  eval::writeDataset(root_ / "run", makeSyntheticDataset(p));  // same pid: the stale one is reused
  EXPECT_EQ(entries(), std::vector<std::string>{"run"});
}

struct Corruption {
  const char* file;
  std::function<void(const fs::path&)> apply;
  std::string expected;  ///< substring after the file path
};

TEST_F(DatasetIo, MalformedFilesAreRejectedNamingFileLineAndField) {
  SyntheticDatasetParams p;
  p.duration_s = 0.5;
  const Dataset d = makeSyntheticDataset(p);
  auto line = [](std::size_t n, std::string text) {
    return [n, text](const fs::path& f) { replaceLine(f, n, text); };
  };
  auto edit = [](std::size_t n, std::function<std::string(const std::string&)> change) {
    return [n, change](const fs::path& f) { replaceLine(f, n, change(lineOf(f, n))); };
  };
  auto erase = [](const fs::path& f) { fs::remove(f); };
  auto jsonEdit = [](const std::string& from, const std::string& to) {
    return [from, to](const fs::path& f) {
      std::string t = slurp(f);
      const auto at = t.find(from);
      ASSERT_NE(at, std::string::npos) << from;
      spit(f, t.replace(at, from.size(), to));
    };
  };
  auto scanEdit = [](std::size_t n, const char* key, nlohmann::json value) {
    return [n, key, value](const fs::path& f) {
      nlohmann::json j = nlohmann::json::parse(lineOf(f, n));
      if (value.is_discarded())
        j.erase(key);
      else
        j[key] = value;
      replaceLine(f, n, j.dump());
    };
  };
  const nlohmann::json erase_key = nlohmann::json::value_t::discarded;
  const std::vector<Corruption> cases = {
      {"imu.csv", erase, ": cannot open file"},
      {"scans.jsonl", erase, ": cannot open file"},
      {"encoders.csv",
       [](const fs::path& f) {
         fs::remove(f);
         fs::create_directory(f);
       },
       ": not a regular file"},
      {"dataset.json", jsonEdit("\"nominal\"", "\"nominal\" ]"), ":11: bad JSON"},
      {"dataset.json", jsonEdit("\"ticks_per_revolution\"", "\"ticks\""),
       ": ticks_per_revolution: missing required key"},
      {"dataset.json", jsonEdit("\"r_L\": 0.1,", "\"r_L\": -0.1,"), ": nominal.r_L: must be > 0"},
      {"dataset.json", jsonEdit("\"ticks_per_revolution\": 4096", "\"ticks_per_revolution\": 0"),
       ": ticks_per_revolution: must be a positive int"},
      {"encoders.csv", line(3, "1,2"), ":3: expected 3 columns"},
      {"encoders.csv", edit(4, [](const std::string& s) { return s + ",7"; }),
       ":4: expected 3 columns"},
      {"encoders.csv",
       edit(5, [](const std::string& s) { return s.substr(0, s.rfind(',')) + ",12x"; }),
       ":5: ticks_right: not an integer"},
      {"encoders.csv", line(1, "t,l,r"), ":1: expected the header"},
      {"encoders.csv",
       edit(6, [&](const std::string&) { return lineOf(root_ / "m/encoders.csv", 5); }),
       ":6: stamp_s: duplicate timestamp"},
      {"imu.csv", edit(3, [](const std::string& s) { return "nan" + s.substr(s.find(',')); }),
       ":3: stamp_s: must be finite"},
      {"imu.csv", edit(4, [](const std::string& s) { return s.substr(0, s.rfind(',')) + ",inf"; }),
       ":4: accel_y_mps2: must be finite"},
      {"imu.csv", edit(2, [](const std::string& s) { return "1e300" + s.substr(s.find(',')); }),
       ":3: stamp_s: timestamp"},
      {"groundtruth.tum",
       // Appended, not "1" + ...: GCC 12 warns falsely (-Wrestrict) on that here.
       edit(10,
            [](const std::string& s) { return std::string("1").append(s.substr(s.find(' '))); }),
       ":10: t: timestamp 1 after"},
      {"groundtruth.tum", line(7, "1 2 3"), ":7: expected 8 columns"},
      {"odom_nominal.tum",
       edit(3, [](const std::string& s) { return std::string(s).replace(s.find(' '), 1, " x "); }),
       ":3: expected 8 columns"},
      {"odom_nominal.tum", edit(4, [](const std::string& s) { return s + "e"; }),
       ":4: qw: not a number"},
      {"scans.jsonl", line(2, "{\"nrays\": 3,"), ":2: bad JSON"},
      {"scans.jsonl", scanEdit(3, "nrays", 719), ":3: readings: has 720 entries but nrays is 719"},
      {"scans.jsonl", scanEdit(2, "readings", erase_key), ":2: readings: missing required key"},
      {"scans.jsonl", scanEdit(4, "stamp_s", 0.0), ":4: stamp_s: timestamp 0 after"},
      {"scans.jsonl", scanEdit(1, "true_pose", {1, 2}), ":1: true_pose: expected [x, y, th]"},
      {"scans.jsonl", scanEdit(2, "p_ref_true", {nullptr}), ":2: p_ref_true: has 1 entries"},
  };
  for (std::size_t c = 0; c < cases.size(); ++c) {
    const fs::path dir = root_ / "m";
    fs::remove_all(dir);
    eval::writeDataset(dir, d);
    cases[c].apply(dir / cases[c].file);
    const std::string expected = (dir / cases[c].file).string() + cases[c].expected;
    try {
      eval::readDataset(dir);
      ADD_FAILURE() << "case " << c << " accepted; expected " << expected;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos)
          << "case " << c << ": " << e.what() << "\nexpected: " << expected;
    }
  }
  EXPECT_THROW(eval::readDataset(root_ / "does_not_exist"), InputError);
}

// The odometry must cover the scans: every beam of every scan, first to last, must lie inside
// the span of each odometry the dataset has (encoders.csv and odom_nominal.tum; an imported log
// may have only one of them). Without any odometry the scans are still readable (ICP-only use).
TEST_F(DatasetIo, ScansOutsideTheOdometryAreRejectedNamingTheScanLine) {
  SyntheticDatasetParams p;
  p.duration_s = 0.5;
  p.beams = 16;
  const Dataset good = makeSyntheticDataset(p);
  ASSERT_EQ(good.scans.size(), 5u);
  // Refused by the writer (nothing is published) and, when the files come from elsewhere, by
  // the reader: the same dataset written by a writer without the check is emulated by writing
  // the covered dataset and replacing its scans.jsonl.
  auto expectRefused = [&](const Dataset& d, const std::string& expected) {
    const fs::path dir = root_ / "cover";
    fs::remove_all(dir);
    const std::string where = (dir / "scans.jsonl").string() + expected;
    try {
      eval::writeDataset(dir, d);
      ADD_FAILURE() << "written; expected " << expected;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(where), std::string::npos) << e.what();
    }
    EXPECT_FALSE(fs::exists(dir));
    Dataset covered = d;
    covered.scans.clear();
    eval::writeDataset(dir, covered);
    spit(dir / "scans.jsonl", eval::formatScans(d.scans, "scans.jsonl"));
    try {
      eval::readDataset(dir);
      ADD_FAILURE() << "read; expected " << expected;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(where), std::string::npos) << e.what();
    }
  };
  // The last scan's last beam 1 ms after the last encoder sample.
  Dataset late = good;
  LaserScan& last = late.scans.back().scan;
  last.time_increment_s = (late.encoders.back().stamp_s + 1e-3 - last.stamp_s) / 15;
  expectRefused(late, ":5: stamp_s: the scan's beams");
  // The first scan starting before the odometry.
  Dataset early = good;
  early.scans.front().scan.stamp_s = early.encoders.front().stamp_s - 1e-6;
  expectRefused(early, ":1: stamp_s:");
  // Only odom_nominal (no encoders), ending 1 ms before the last beam: checked against it.
  Dataset odom_only = good;
  odom_only.encoders.clear();
  PoseSeries shorter;
  for (const auto& s : good.odom_nominal.samples())
    if (s.stamp_s < good.scans.back().scan.endTime() - 1e-3) shorter.push_back(s.stamp_s, s.value);
  odom_only.odom_nominal = shorter;
  expectRefused(odom_only, ":5: stamp_s:");
  // Only encoders: checked against them.
  Dataset encoders_only = late;
  encoders_only.odom_nominal = PoseSeries{};
  expectRefused(encoders_only, ":5: stamp_s:");
  // Covered scans read back; so do scans of a dataset with no odometry at all.
  eval::writeDataset(root_ / "ok", good);
  EXPECT_EQ(eval::readDataset(root_ / "ok").scans.size(), 5u);
  Dataset no_odometry = late;
  no_odometry.encoders.clear();
  no_odometry.odom_nominal = PoseSeries{};
  eval::writeDataset(root_ / "scans_only", no_odometry);
  EXPECT_EQ(eval::readDataset(root_ / "scans_only").scans.size(), 5u);
}

TEST_F(DatasetIo, TruncatedOrGarbledFilesNeverCrashTheReader) {
  SyntheticDatasetParams p;
  p.duration_s = 0.3;
  p.beams = 16;
  const Dataset d = makeSyntheticDataset(p);
  const fs::path dir = root_ / "fuzz";
  eval::writeDataset(dir, d);
  std::mt19937 rng(5);
  int rejected = 0, trials = 0;
  for (const char* file : {"dataset.json", "groundtruth.tum", "odom_nominal.tum", "encoders.csv",
                           "imu.csv", "scans.jsonl"}) {
    const std::string original = slurp(dir / file);
    for (int k = 0; k < 40; ++k) {
      std::string text = original;
      std::uniform_int_distribution<std::size_t> at(0, text.size() - 1);
      if (k % 2)
        text.resize(at(rng));  // truncated mid-write by someone else's tool
      else
        text[at(rng)] = "x,.-e\n\"[]{}0 "[rng() % 14];  // one garbled byte
      spit(dir / file, text);
      ++trials;
      try {
        eval::readDataset(dir);
      } catch (const InputError&) {
        ++rejected;
      }
    }
    spit(dir / file, original);
  }
  // Most damage is detected; some is benign (a digit in a number, a cut at a line end).
  EXPECT_GT(rejected, trials / 3);
}

}  // namespace
}  // namespace slamprep
