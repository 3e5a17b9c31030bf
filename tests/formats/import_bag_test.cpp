// Importing ROS 2 bags: a folder of split .mcap files, compressed chunks, streaming, the nominal
// geometry (never guessed), JointState ticks, scans without beam timing, the export round trip.
#include <gtest/gtest.h>

#include <filesystem>
#include <numbers>

#include "bag_writer.hpp"
#include "export_input.hpp"
#include "slamprep/core/atomic_file.hpp"
#include "slamprep/core/error.hpp"
#include "slamprep/core/odometry.hpp"
#include "slamprep/eval/formats/byte_source.hpp"
#include "slamprep/eval/formats/export.hpp"
#include "slamprep/eval/formats/import.hpp"
#include "slamprep/tests/support/scratch_dir.hpp"
#include "synthetic_dataset.hpp"

namespace slamprep::eval {
namespace {
namespace fs = std::filesystem;

/// The part of a dataset with stamps in [from, to).
Dataset slice(const Dataset& d, double from, double to) {
  Dataset out;
  out.info = d.info;
  auto in = [&](double t) { return t >= from && t < to; };
  for (const auto& s : d.scans)
    if (in(s.scan.stamp_s)) out.scans.push_back(s);
  for (const auto& e : d.encoders)
    if (in(e.stamp_s)) out.encoders.push_back(e);
  for (const auto& s : d.imu)
    if (in(s.stamp_s)) out.imu.push_back(s);
  for (const auto& s : d.odom_nominal.samples())
    if (in(s.stamp_s)) out.odom_nominal.push_back(s.stamp_s, s.value);
  for (const auto& s : d.groundtruth.samples())
    if (in(s.stamp_s)) out.groundtruth.push_back(s.stamp_s, s.value);
  return out;
}

void expectSameImport(const Dataset& a, const Dataset& b) {
  ASSERT_EQ(a.scans.size(), b.scans.size());
  for (std::size_t k = 0; k < a.scans.size(); ++k) {
    ASSERT_EQ(a.scans[k].scan.stamp_s, b.scans[k].scan.stamp_s) << k;
    ASSERT_EQ(a.scans[k].scan.ranges_m, b.scans[k].scan.ranges_m) << k;
  }
  ASSERT_EQ(a.encoders.size(), b.encoders.size());
  for (std::size_t k = 0; k < a.encoders.size(); ++k) {
    ASSERT_EQ(a.encoders[k].ticks_left, b.encoders[k].ticks_left) << k;
    ASSERT_EQ(a.encoders[k].ticks_right, b.encoders[k].ticks_right) << k;
  }
  EXPECT_EQ(a.imu.size(), b.imu.size());
  EXPECT_EQ(a.info.T_base_lidar.x, b.info.T_base_lidar.x);
  EXPECT_EQ(a.info.nominal_geometry.wheel_base_m, b.info.nominal_geometry.wheel_base_m);
}

TEST(ImportBag, FolderWithSplitFilesIsReadInTheOrderOfMetadataYaml) {
  const Dataset d = test::makeSyntheticDataset();
  // Two files split at 1 s; the second has one more channel first, so its channel ids differ.
  ExportInput first, second;
  first.dataset = slice(d, 0.0, 1.0);
  second.dataset = slice(d, 1.0, 10.0);
  second.deskewed["linear"] = second.dataset.scans;
  const test::ScratchDir scratch("import_bag");
  const fs::path dir = scratch / "split_bag";
  fs::create_directories(dir);
  writeFileAtomic(dir / "split_bag_0.mcap", formatMcap(first, {}));
  writeFileAtomic(dir / "split_bag_1.mcap", formatMcap(second, {}));
  writeFileAtomic(dir / "metadata.yaml",
                  "rosbag2_bagfile_information:\n  version: 5\n  storage_identifier: mcap\n"
                  "  relative_file_paths:\n    - split_bag_0.mcap\n    - split_bag_1.mcap\n"
                  "  compression_format: \"\"\n  compression_mode: \"\"\n");
  ImportParams p;
  p.ticks_per_revolution = d.info.ticks_per_revolution;
  const ImportResult split = importMcap(dir, p);
  EXPECT_EQ(split.dataset.info.config.at("bag_files"), "2");
  ExportInput whole;
  whole.dataset = d;
  expectSameImport(split.dataset, importMcap(formatMcap(whole, {}), "whole.mcap", p).dataset);
  EXPECT_EQ(split.dataset.encoders.size(), d.encoders.size());

  // Listed in the wrong order, the second file's stamps come first: still sorted by log time.
  writeFileAtomic(dir / "metadata.yaml",
                  "rosbag2_bagfile_information:\n  storage_identifier: mcap\n"
                  "  relative_file_paths: [split_bag_1.mcap, split_bag_0.mcap]\n");
  expectSameImport(importMcap(dir, p).dataset, split.dataset);
}

std::string errorOf(const fs::path& bag) {
  try {
    importMcap(bag, ImportParams{});
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(ImportBag, FoldersThatAreNotBagsAreRefusedSayingWhy) {
  const test::ScratchDir scratch("import_bag");
  const fs::path dir = scratch / "not_a_bag";
  fs::create_directories(dir);
  EXPECT_NE(errorOf(dir).find("ros2 bag reindex"), std::string::npos) << errorOf(dir);
  writeFileAtomic(dir / "metadata.yaml",
                  "rosbag2_bagfile_information:\n  storage_identifier: sqlite3\n"
                  "  relative_file_paths: [a_0.db3]\n");
  EXPECT_NE(errorOf(dir).find("a_0.db3 not found"), std::string::npos) << errorOf(dir);
  writeFileAtomic(dir / "metadata.yaml",
                  "rosbag2_bagfile_information:\n  storage_identifier: mcap\n"
                  "  relative_file_paths: [a_0.mcap]\n");
  EXPECT_NE(errorOf(dir).find("a_0.mcap not found"), std::string::npos) << errorOf(dir);
  writeFileAtomic(dir / "metadata.yaml",
                  "rosbag2_bagfile_information:\n  storage_identifier: mcap\n"
                  "  compression_mode: FILE\n  compression_format: zstd\n"
                  "  relative_file_paths: [a_0.mcap.zstd]\n");
  EXPECT_NE(errorOf(dir).find("a_0.mcap.zstd not found"), std::string::npos) << errorOf(dir);
  EXPECT_NE(errorOf(dir / "missing.mcap").find("no such file"), std::string::npos);
  // A repeated key is refused, not read as one of its values (which one yaml-cpp keeps is not
  // documented): the second storage_identifier, line 3, column 3.
  writeFileAtomic(dir / "metadata.yaml",
                  "rosbag2_bagfile_information:\n  storage_identifier: mcap\n"
                  "  storage_identifier: sqlite3\n  relative_file_paths: [a_0.mcap]\n");
  EXPECT_NE(errorOf(dir).find("metadata.yaml:3:3: storage_identifier: key appears twice in one "
                              "mapping (first on line 2)"),
            std::string::npos)
      << errorOf(dir);
  std::string deep = "rosbag2_bagfile_information: ";
  for (int i = 0; i < 70; ++i) deep += "[";
  writeFileAtomic(dir / "metadata.yaml", deep + std::string(70, ']') + "\n");
  EXPECT_NE(errorOf(dir).find("YAML nested deeper than 64 levels"), std::string::npos)
      << errorOf(dir);
}

/// A source that records how much it is asked for at once.
class CountingSource final : public ByteSource {
 public:
  explicit CountingSource(std::string_view bytes) : inner_(memorySource(bytes, "count.mcap")) {}
  const std::string& name() const override { return inner_->name(); }
  std::uint64_t size() const override { return inner_->size(); }
  void read(std::uint64_t offset, std::size_t n, std::string& out) override {
    largest = std::max(largest, n);
    total += n;
    inner_->read(offset, n, out);
  }
  std::size_t largest = 0, total = 0;

 private:
  std::unique_ptr<ByteSource> inner_;
};

TEST(ImportBag, TheReaderPullsOneChunkAtATime) {
  const ExportInput in = test::syntheticInput();
  ExportParams ep;
  ep.mcap_chunk_size_bytes = 4 * 1024;       // hundreds of chunks
  ep.mcap_compression = Compression::kNone;  // a file of about 1 MiB
  const std::string bag = formatMcap(in, ep);
  CountingSource source(bag);
  McapReader reader(source);
  McapMessage m;
  std::size_t messages = 0;
  while (reader.next(m)) ++messages;
  EXPECT_GT(reader.chunkCount(), 150u);
  EXPECT_TRUE(reader.dataCrcChecked());
  // A chunk closes once its records pass 4 KiB (the longest message, a 360-beam scan, is under
  // 1.6 KiB) and CRCs are taken over blocks of 64 KiB at most, so no read asks for more than
  // 64 KiB of a file of about 1 MiB. Every byte is read about once (the summary twice: its CRC
  // at open, its records for the topics).
  EXPECT_GT(bag.size(), 900u * 1024);
  EXPECT_LE(source.largest, 64u * 1024) << "of " << bag.size();
  EXPECT_LT(source.total, bag.size() * 3 / 2);
  const auto& d = in.dataset;
  EXPECT_EQ(messages, 2 * d.scans.size() + 2 * d.odom_nominal.size() + 2 * d.encoders.size() +
                          d.imu.size() + d.groundtruth.size() + 1);
  // The import of the many-chunk bag equals that of a single-chunk one.
  ImportParams p;
  ExportParams one;
  one.mcap_chunk_size_bytes = std::size_t{1} << 30;
  expectSameImport(importMcap(bag, "many.mcap", p).dataset,
                   importMcap(formatMcap(in, one), "one.mcap", p).dataset);
}

TEST(ImportBag, ExportedBagsRoundTripFromDiskWithEveryCompression) {
  const ExportInput in = test::syntheticInput();
  const Dataset& d = in.dataset;
  const test::ScratchDir scratch("import_bag");
  for (const Compression c : {Compression::kZstd, Compression::kLz4, Compression::kNone}) {
    ExportParams ep;
    ep.mcap_compression = c;
    ep.mcap_chunk_size_bytes = 64 * 1024;
    const fs::path file = scratch / ("rt_" + std::string(mcapCompressionName(c)) + ".mcap");
    exportDataset(in, ExportFormat::kMcap, file, ep);
    ImportParams p;  // no geometry: the bag's slamprep Metadata record carries it
    p.ticks_per_revolution = d.info.ticks_per_revolution;
    const ImportResult r = importMcap(file, p);
    const Dataset& back = r.dataset;
    EXPECT_EQ(back.info.nominal_geometry.radius_left_m, d.info.nominal_geometry.radius_left_m);
    EXPECT_EQ(back.info.nominal_geometry.radius_right_m, d.info.nominal_geometry.radius_right_m);
    EXPECT_EQ(back.info.nominal_geometry.wheel_base_m, d.info.nominal_geometry.wheel_base_m);
    ASSERT_EQ(back.encoders.size(), d.encoders.size());
    for (std::size_t k = 0; k < d.encoders.size(); ++k) {
      ASSERT_EQ(back.encoders[k].ticks_left, d.encoders[k].ticks_left);
      ASSERT_EQ(back.encoders[k].ticks_right, d.encoders[k].ticks_right);
    }
    ASSERT_EQ(back.scans.size(), d.scans.size());
    EXPECT_EQ(back.scans[3].scan.ranges_m[10], double(float(d.scans[3].scan.ranges_m[10])));
    EXPECT_NEAR(back.info.T_base_lidar.yaw, d.info.T_base_lidar.yaw, 1e-15);
    EXPECT_EQ(back.info.config.at("lidar_mount_from"), "tf base_link -> laser");
    // The nominal odometry re-integrated from the same ticks and geometry is the original.
    EXPECT_NEAR(back.odom_nominal.samples().back().value.x, d.odom_nominal.samples().back().value.x,
                1e-12);
  }
}

TEST(ImportBag, RefusesWithoutNominalGeometryWhenTheTicksNeedIt) {
  test::RobotBagParams b;
  b.joint_states = false;
  for (const bool joints : {false, true}) {
    b.joint_states = joints;
    const std::string bag = test::robotBag(b);
    try {
      importMcap(bag, "robot.mcap", ImportParams{});
      ADD_FAILURE() << "imported without a nominal geometry";
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("no nominal wheel geometry"), std::string::npos) << what;
      EXPECT_NE(what.find(joints ? "JointState ticks" : "derived from the Odometry poses"),
                std::string::npos)
          << what;
      EXPECT_NE(what.find("--nominal r_L,r_R,b"), std::string::npos) << what;
    }
    ImportParams p;
    p.nominal_geometry = DiffDriveParams{0.1, 0.1, 0.5};
    EXPECT_EQ(importMcap(bag, "robot.mcap", p).dataset.scans.size(), 3u);
  }
}

TEST(ImportBag, JointStatesBecomeTicksOfTheNamedWheels) {
  test::RobotBagParams b;
  b.joints = {"wheel_l", "wheel_r"};  // no "left"/"right" in the names
  ImportParams p;
  p.nominal_geometry = DiffDriveParams{0.1, 0.1, 0.5};
  try {
    importMcap(test::robotBag(b), "j.mcap", p);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("[wheel_l, wheel_r]: choose with --left-joint"),
              std::string::npos)
        << e.what();
  }
  p.left_joint = "wheel_l";
  p.right_joint = "wheel_r";
  const Dataset d = importMcap(test::robotBag(b), "j.mcap", p).dataset;
  ASSERT_EQ(d.encoders.size(), 51u);
  // Left 1 rad/s, right 3 rad/s for 1 s: ticks round(angle / (2 pi / 2^20)).
  const double rad_per_tick = radiansPerTick(p.ticks_per_revolution);
  EXPECT_EQ(d.encoders.back().ticks_left, std::llround(1.0 / rad_per_tick));
  EXPECT_EQ(d.encoders.back().ticks_right, std::llround(3.0 / rad_per_tick));
  // Integrated with r = 0.1, b = 0.5: v = 0.2 m/s, w = 0.4 rad/s, an arc from the logged odometry
  // at 10 s (the origin): (v/w sin(w t), v/w (1 - cos(w t)), w t) at t = 1 s. Ticks round to
  // 3e-6 rad, well under the 1e-6 m tolerance on a 0.1 m wheel.
  const SE2& end = d.odom_nominal.samples().back().value;
  EXPECT_NEAR(end.x, 0.5 * std::sin(0.4), 1e-6);
  EXPECT_NEAR(end.y, 0.5 * (1 - std::cos(0.4)), 1e-6);
  EXPECT_NEAR(end.yaw, 0.4, 1e-6);
}

TEST(ImportBag, ScansWithoutBeamTimingAreKeptWithANoteOrGivenOne) {
  test::RobotBagParams b;
  b.time_increment_s = 0.0f;
  ImportParams p;
  p.nominal_geometry = DiffDriveParams{0.1, 0.1, 0.5};
  const ImportResult r = importMcap(test::robotBag(b), "t.mcap", p);
  ASSERT_EQ(r.dataset.scans.size(), 3u);
  EXPECT_EQ(r.dataset.scans[1].scan.time_increment_s, 0.0);
  bool noted = false, hinted = false;
  for (const auto& n : r.notes) {
    noted = noted || n.find("3 of 3 scans have time_increment 0") != std::string::npos;
    // Scans every 0.3 s, beams 0.25 rad apart: one turn per scan is 0.3 x 0.25 / 2 pi s a beam.
    hinted = hinted || n.find("would have 0.0119 s") != std::string::npos;
  }
  EXPECT_TRUE(noted);
  EXPECT_TRUE(hinted);
  p.time_increment_s = 2e-4;
  const ImportResult given = importMcap(test::robotBag(b), "t.mcap", p);
  for (const auto& s : given.dataset.scans) EXPECT_EQ(s.scan.time_increment_s, 2e-4);
  for (const auto& n : given.notes) EXPECT_EQ(n.find("time_increment 0"), std::string::npos) << n;
}

// A spilled import (what `slamprep import` does with a bag) hands out the scans the in-memory
// import holds, bit for bit: mirrored for an upside-down lidar, time increments as given, the
// odometry attached; the notes are the same and the spill file is gone with the stream.
TEST(ImportBag, SpilledScansAreTheScansOfTheInMemoryImport) {
  test::RobotBagParams b;
  b.tf_static = {test::transform("base_link", "laser",
                                 test::pose3(0.2, -0.1, 0.3, std::numbers::pi, 0.0, 0.4))};
  b.time_increment_s = 0.0f;
  const test::ScratchDir scratch("import_bag");
  const fs::path file = scratch / "spill.mcap";
  writeFileAtomic(file, test::robotBag(b));
  const fs::path spill_dir = scratch / "spill_dir";
  fs::create_directories(spill_dir);
  ImportParams p;
  p.nominal_geometry = DiffDriveParams{0.1, 0.1, 0.5};
  const ImportResult memory = importMcap(file, p);
  p.spill_dir = spill_dir;
  ImportResult spilled = importMcap(file, p);
  ASSERT_TRUE(spilled.scans);
  EXPECT_TRUE(spilled.dataset.scans.empty());
  EXPECT_FALSE(fs::is_empty(spill_dir));
  std::vector<ScanRecord> streamed;
  for (ScanRecord r; spilled.scans->next(r);) streamed.push_back(r);
  ASSERT_EQ(streamed.size(), memory.dataset.scans.size());
  EXPECT_EQ(spilled.scans->count(), streamed.size());
  for (std::size_t k = 0; k < streamed.size(); ++k) {
    const LaserScan &a = streamed[k].scan, &m = memory.dataset.scans[k].scan;
    EXPECT_EQ(a.stamp_s, m.stamp_s);
    EXPECT_EQ(a.angle_min_rad, m.angle_min_rad);
    EXPECT_EQ(a.angle_increment_rad, m.angle_increment_rad);
    EXPECT_EQ(a.time_increment_s, m.time_increment_s);
    EXPECT_EQ(a.ranges_m, m.ranges_m);
    ASSERT_TRUE(streamed[k].T_odom_base_nominal);
    EXPECT_EQ(streamed[k].T_odom_base_nominal->x, memory.dataset.scans[k].T_odom_base_nominal->x);
  }
  EXPECT_LT(memory.dataset.scans[0].scan.angle_increment_rad, 0.0);  // mirrored in both
  std::vector<std::string> notes = spilled.notes;
  for (const std::string& n : spilled.scans->notes()) notes.push_back(n);
  EXPECT_EQ(notes, memory.notes);
  spilled.scans.reset();
  EXPECT_TRUE(fs::is_empty(spill_dir));
  // --time-increment auto: both give a scan with 0 one turn of the same median period (scans
  // every 0.3 s, beams 0.25 rad apart).
  p.time_increment_one_turn = true;
  p.spill_dir.clear();
  const ImportResult memory_auto = importMcap(file, p);
  p.spill_dir = spill_dir;
  ImportResult spilled_auto = importMcap(file, p);
  std::size_t k = 0;
  for (ScanRecord r; spilled_auto.scans->next(r); ++k) {
    ASSERT_LT(k, memory_auto.dataset.scans.size());
    EXPECT_EQ(r.scan.time_increment_s, memory_auto.dataset.scans[k].scan.time_increment_s);
    EXPECT_NEAR(r.scan.time_increment_s, 0.3 * 0.25 / (2.0 * std::numbers::pi), 1e-7);
  }
  EXPECT_EQ(k, memory_auto.dataset.scans.size());
}

}  // namespace
}  // namespace slamprep::eval
