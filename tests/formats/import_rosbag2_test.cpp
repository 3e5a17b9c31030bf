// rosbag2 bags as robots record them: sqlite3 storage (.db3), split files, zstd compression per
// file and per message, every metadata.yaml version; the same messages must give the same
// dataset from either storage, the input folder must stay byte for byte as it was, and broken
// bags are refused naming the file.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>

#include "export_input.hpp"
#include "slamprep/core/atomic_file.hpp"
#include "slamprep/core/error.hpp"
#include "slamprep/eval/formats/export.hpp"
#include "slamprep/eval/formats/import.hpp"
#include "slamprep/eval/formats/rosbag2.hpp"
#include "slamprep/eval/formats/text_io.hpp"
#include "slamprep/tests/support/scratch_dir.hpp"
#include "sqlite_bag.hpp"

namespace slamprep::eval {
namespace {
namespace fs = std::filesystem;

/// The synthetic dataset exported to MCAP, and its messages.
struct Source {
  std::string mcap;
  McapFile file;
  ImportParams params;
};

const Source& source() {
  static const Source s = [] {
    Source out;
    ExportParams ep;
    ep.mcap_compression = Compression::kNone;
    out.mcap = formatMcap(test::syntheticInput(), ep);
    out.file = readMcap(out.mcap, "synthetic.mcap");
    // A .db3 cannot carry slamprep's Metadata record: the geometry is given to both imports.
    out.params.nominal_geometry = test::syntheticInput().dataset.info.nominal_geometry;
    out.params.ticks_per_revolution = 4096;
    return out;
  }();
  return s;
}

void expectSameDataset(const Dataset& a, const Dataset& b) {
  ASSERT_EQ(a.scans.size(), b.scans.size());
  for (std::size_t k = 0; k < a.scans.size(); ++k) {
    ASSERT_EQ(a.scans[k].scan.stamp_s, b.scans[k].scan.stamp_s) << k;
    ASSERT_EQ(a.scans[k].scan.ranges_m, b.scans[k].scan.ranges_m) << k;
    ASSERT_EQ(a.scans[k].T_odom_base_nominal->x, b.scans[k].T_odom_base_nominal->x) << k;
  }
  ASSERT_EQ(a.encoders.size(), b.encoders.size());
  for (std::size_t k = 0; k < a.encoders.size(); ++k) {
    ASSERT_EQ(a.encoders[k].ticks_left, b.encoders[k].ticks_left) << k;
    ASSERT_EQ(a.encoders[k].ticks_right, b.encoders[k].ticks_right) << k;
  }
  ASSERT_EQ(a.odom_nominal.size(), b.odom_nominal.size());
  for (std::size_t k = 0; k < a.odom_nominal.size(); ++k)
    ASSERT_EQ(a.odom_nominal[k].value.yaw, b.odom_nominal[k].value.yaw) << k;
  ASSERT_EQ(a.imu.size(), b.imu.size());
  for (std::size_t k = 0; k < a.imu.size(); ++k)
    ASSERT_EQ(a.imu[k].gyro_z_radps, b.imu[k].gyro_z_radps) << k;
  EXPECT_EQ(a.info.T_base_lidar.x, b.info.T_base_lidar.x);
  EXPECT_EQ(a.info.T_base_lidar.yaw, b.info.T_base_lidar.yaw);
  EXPECT_EQ(a.info.config.at("encoders_from"), b.info.config.at("encoders_from"));
}

const Dataset& fromMcap() {
  static const Dataset d = importMcap(source().mcap, "synthetic.mcap", source().params).dataset;
  return d;
}

/// Every file of a folder and its bytes.
std::map<std::string, std::string> snapshot(const fs::path& dir) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::directory_iterator(dir))
    files[e.path().filename()] = readTextFile(e.path());
  return files;
}

std::string importErrorOf(const fs::path& bag, const ImportParams& p = source().params) {
  try {
    importRosbag2(bag, p);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(ImportRosbag2, ASqliteBagGivesTheDatasetOfTheMcapBagOfTheSameMessages) {
  const test::ScratchDir scratch("rosbag2");
  const fs::path dir = scratch / "bag";
  fs::create_directories(dir);
  test::writeSqliteBag(dir / "bag_0.db3", source().file);
  writeFileAtomic(dir / "metadata.yaml", test::metadataYaml(4, "sqlite3", {"bag_0.db3"}));
  const auto before = snapshot(dir);
  const ImportResult r = importRosbag2(dir, source().params);
  expectSameDataset(r.dataset, fromMcap());
  EXPECT_EQ(r.dataset.info.config.at("format"), "sqlite3");
  EXPECT_EQ(r.summary.storage, "sqlite3, 1 file (metadata.yaml version 4)");
  // One .db3 without its folder: recognised by its magic.
  expectSameDataset(importRosbag2(dir / "bag_0.db3", source().params).dataset, fromMcap());
  // Read-only and immutable: no -wal, -shm or journal appeared, not a byte changed.
  EXPECT_EQ(snapshot(dir), before);
  EXPECT_EQ(before.size(), 2u);
}

TEST(ImportRosbag2, ARecordingNotClosedIsReadWithItsWal) {
  const test::ScratchDir scratch("rosbag2");
  const fs::path dir = scratch / "open";
  fs::create_directories(dir);
  test::SqliteBagParams p;
  p.copy_open_to = dir / "open_0.db3";
  test::writeSqliteBag(scratch / "recording.db3", source().file, p);
  ASSERT_GT(fs::file_size(dir / "open_0.db3-wal"), 0u);
  writeFileAtomic(dir / "metadata.yaml", test::metadataYaml(4, "sqlite3", {"open_0.db3"}));
  const auto before = snapshot(dir);
  const ImportResult r = importRosbag2(dir, source().params);
  expectSameDataset(r.dataset, fromMcap());
  bool noted = false;
  for (const auto& n : r.notes) noted = noted || n.find("non-empty -wal") != std::string::npos;
  EXPECT_TRUE(noted);
  EXPECT_EQ(snapshot(dir), before);  // recovered in a private copy, not in the user's folder
}

TEST(ImportRosbag2, SplitDb3FilesAreReadInTheOrderOfMetadataYaml) {
  const test::ScratchDir scratch("rosbag2");
  const fs::path dir = scratch / "split";
  fs::create_directories(dir);
  const std::uint64_t cut = source().file.messages[source().file.messages.size() / 2].log_time_ns;
  test::writeSqliteBag(dir / "split_0.db3", source().file, {},
                       [&](std::uint64_t t) { return t < cut; });
  test::writeSqliteBag(dir / "split_1.db3", source().file, {},
                       [&](std::uint64_t t) { return t >= cut; });
  writeFileAtomic(dir / "metadata.yaml",
                  test::metadataYaml(5, "sqlite3", {"split_0.db3", "split_1.db3"}));
  const ImportResult r = importRosbag2(dir, source().params);
  EXPECT_EQ(r.dataset.info.config.at("bag_files"), "2");
  expectSameDataset(r.dataset, fromMcap());
}

TEST(ImportRosbag2, EveryMetadataVersionIsRead) {
  const test::ScratchDir scratch("rosbag2");
  const fs::path dir = scratch / "versions";
  fs::create_directories(dir);
  test::SqliteBagParams newer;
  newer.type_description_hash = newer.newer_tables = true;
  test::writeSqliteBag(dir / "v_0.db3", source().file, newer);
  for (const int version : {4, 5, 6, 7, 8, 9}) {
    writeFileAtomic(dir / "metadata.yaml", test::metadataYaml(version, "sqlite3", {"v_0.db3"}));
    const Rosbag2Bag bag = readRosbag2(dir);
    EXPECT_EQ(bag.version, version);
    EXPECT_EQ(bag.storage, BagStorageKind::kSqlite3);
    expectSameDataset(importRosbag2(dir, source().params).dataset, fromMcap());
  }
}

/// The MCAP source again with each message's bytes one zstd frame (compression_mode MESSAGE).
std::string mcapWithZstdMessages(const McapFile& in) {
  McapWriter w;
  std::map<std::uint16_t, std::uint16_t> schema, channel;
  for (const auto& [id, s] : in.schemas) schema[id] = w.addSchema(s.name, s.encoding, s.data);
  for (const auto& [id, c] : in.channels)
    channel[id] = w.addChannel(schema.at(c.schema_id), c.topic, c.message_encoding);
  for (const auto& m : in.messages)
    w.addMessage(channel.at(m.channel_id), m.log_time_ns, m.publish_time_ns,
                 compressChunk(Compression::kZstd, m.data));
  return w.finish();
}

TEST(ImportRosbag2, MessageCompressionIsReadForBothStorages) {
  const test::ScratchDir scratch("rosbag2");
  for (const std::string storage : {"sqlite3", "mcap"}) {
    const fs::path dir = scratch / ("message_" + storage);
    fs::create_directories(dir);
    const std::string file = storage == "mcap" ? "m_0.mcap" : "m_0.db3";
    if (storage == "mcap") {
      writeFileAtomic(dir / file, mcapWithZstdMessages(source().file));
    } else {
      test::SqliteBagParams p;
      p.message_zstd = true;
      test::writeSqliteBag(dir / file, source().file, p);
    }
    writeFileAtomic(dir / "metadata.yaml",
                    test::metadataYaml(8, storage, {file}, "MESSAGE", "zstd"));
    const ImportResult r = importRosbag2(dir, source().params);
    expectSameDataset(r.dataset, fromMcap());
    EXPECT_NE(r.summary.storage.find("compression_mode MESSAGE zstd"), std::string::npos);
  }
}

/// Names in `dir` that start with `prefix`.
std::size_t countPrefixed(const fs::path& dir, const std::string& prefix) {
  std::size_t n = 0;
  for (const auto& e : fs::directory_iterator(dir))
    n += e.path().filename().string().rfind(prefix, 0) == 0;
  return n;
}

TEST(ImportRosbag2, FileCompressionIsUnpackedIntoAScratchFolderThatIsRemoved) {
  const test::ScratchDir scratch("rosbag2");
  const std::string ours = ".slamprep-bag-" + std::to_string(::getpid()) + "-";
  for (const std::string storage : {"sqlite3", "mcap"}) {
    const fs::path dir = scratch / ("file_" + storage);
    fs::create_directories(dir);
    const std::string file = storage == "mcap" ? "f_0.mcap" : "f_0.db3";
    if (storage == "mcap")
      writeFileAtomic(scratch / file, source().mcap);
    else
      test::writeSqliteBag(scratch / file, source().file);
    writeFileAtomic(dir / (file + ".zstd"),
                    compressChunk(Compression::kZstd, readTextFile(scratch / file)));
    writeFileAtomic(dir / "metadata.yaml",
                    test::metadataYaml(6, storage, {file + ".zstd"}, "FILE", "zstd"));
    const auto before = snapshot(dir);
    const std::size_t temp_before = countPrefixed(fs::temp_directory_path(), ours);
    const ImportResult r = importRosbag2(dir, source().params);
    expectSameDataset(r.dataset, fromMcap());
    EXPECT_EQ(countPrefixed(fs::temp_directory_path(), ours), temp_before);
    EXPECT_EQ(snapshot(dir), before);  // never unpacked next to the input
    // Into the spill directory when there is one (the dataset being written), and removed.
    ImportParams spilled = source().params;
    spilled.spill_dir = scratch / ("spill_" + storage);
    fs::create_directories(spilled.spill_dir);
    ImportResult s = importRosbag2(dir, spilled);
    EXPECT_EQ(countPrefixed(spilled.spill_dir, ".slamprep-bag-"), 0u);
    s.scans.reset();
    EXPECT_TRUE(fs::is_empty(spilled.spill_dir));
    // One compressed file without metadata.yaml: its zstd magic and its name say what it is.
    expectSameDataset(importRosbag2(dir / (file + ".zstd"), source().params).dataset, fromMcap());
  }
}

// A bag whose folder and file were renamed after recording: metadata.yaml names a file the folder
// does not hold. With as many storage files held as listed, those are read, and the import says
// so; where it could be another bag's file (more held than listed), it is refused naming them.
TEST(ImportRosbag2, ARenamedBagIsReadFromTheFilesItsFolderHolds) {
  const test::ScratchDir scratch("rosbag2");
  const fs::path dir = scratch / "obstacle_avoider";
  fs::create_directories(dir);
  test::writeSqliteBag(dir / "obstacle_avoider_0.db3", source().file);
  writeFileAtomic(dir / "metadata.yaml", test::metadataYaml(5, "sqlite3", {"object_0.db3"}));
  const ImportResult r = importRosbag2(dir, source().params);
  expectSameDataset(r.dataset, fromMcap());
  ASSERT_FALSE(r.notes.empty());
  EXPECT_NE(r.notes.front().find("read obstacle_avoider_0.db3 instead"), std::string::npos)
      << r.notes.front();
  // Split, renamed: read in split order, _2 before _10 (twelve files listed, twelve held).
  const fs::path split = scratch / "split";
  fs::create_directories(split);
  std::vector<std::string> listed;
  for (int i = 0; i < 12; ++i) {
    test::writeSqliteBag(split / ("renamed_" + std::to_string(i) + ".db3"), source().file);
    listed.push_back("old_" + std::to_string(i) + ".db3");
  }
  writeFileAtomic(split / "metadata.yaml", test::metadataYaml(5, "sqlite3", listed));
  const Rosbag2Bag bag = readRosbag2(split);
  ASSERT_EQ(bag.files.size(), 12u);
  for (int i = 0; i < 12; ++i)
    EXPECT_EQ(bag.files[i].filename(), "renamed_" + std::to_string(i) + ".db3");
  test::writeSqliteBag(dir / "other_0.db3", source().file);
  EXPECT_NE(importErrorOf(dir).find("object_0.db3 not found in " + dir.string() +
                                    " (it holds obstacle_avoider_0.db3, other_0.db3)"),
            std::string::npos)
      << importErrorOf(dir);
}

TEST(ImportRosbag2, BrokenBagsAreRefusedNamingTheFile) {
  const test::ScratchDir scratch("rosbag2");
  const fs::path dir = scratch / "broken";
  fs::create_directories(dir);
  test::writeSqliteBag(dir / "b_0.db3", source().file);
  const std::string db = readTextFile(dir / "b_0.db3");
  auto refused = [&](const std::string& yaml, const std::string& expected) {
    writeFileAtomic(dir / "metadata.yaml", yaml);
    const std::string what = importErrorOf(dir);
    EXPECT_NE(what.find(expected), std::string::npos) << what;
  };
  refused(test::metadataYaml(5, "sqlite3", {"b_0.db3", "b_1.db3"}), "b_1.db3 not found");
  refused(test::metadataYaml(5, "rosbag_v1", {"b_0.db3"}),
          "storage_identifier \"rosbag_v1\" is not read (only sqlite3 and mcap)");
  refused(test::metadataYaml(5, "sqlite3", {"b_0.db3"}, "FILE", "lz4"),
          "compression_format \"lz4\"");
  refused(test::metadataYaml(5, "sqlite3", {"b_0.db3"}, "CHUNK", "zstd"),
          "compression_mode \"CHUNK\" is unknown");
  refused(test::metadataYaml(5, "sqlite3", {"b_0.db3"}, "MESSAGE", "zstd"),
          "b_0.db3: messages row ");  // the blobs are not zstd frames
  // A .db3 that is not a database, one cut short, one whose pages are overwritten.
  writeFileAtomic(dir / "metadata.yaml", test::metadataYaml(5, "sqlite3", {"b_0.db3"}));
  writeFileAtomic(dir / "b_0.db3", "this is not an SQLite database, only text: 0123456789");
  EXPECT_NE(importErrorOf(dir).find("b_0.db3: "), std::string::npos) << importErrorOf(dir);
  writeFileAtomic(dir / "b_0.db3", db.substr(0, db.size() / 2));
  EXPECT_NE(importErrorOf(dir).find("b_0.db3"), std::string::npos) << importErrorOf(dir);
  std::string scrambled = db;
  for (std::size_t i = 4096; i < scrambled.size(); i += 7) scrambled[i] = char(i * 31);
  writeFileAtomic(dir / "b_0.db3", scrambled);
  EXPECT_NE(importErrorOf(dir).find("b_0.db3"), std::string::npos) << importErrorOf(dir);
  // A folder without metadata.yaml says how to rebuild it.
  fs::remove(dir / "metadata.yaml");
  EXPECT_NE(importErrorOf(dir).find("ros2 bag reindex"), std::string::npos);
}

}  // namespace
}  // namespace slamprep::eval
