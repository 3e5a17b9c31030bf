#pragma once
// A ROS 2 bag opened for reading: every storage file of readRosbag2 as a BagStorage. Files that
// rosbag2 compressed whole (compression_mode FILE) are unpacked into a scratch folder, and a .db3
// with a non-empty -wal beside it (a recording that was not closed) is copied there with it so
// SQLite can recover the pages the WAL holds; never anything next to the input. The scratch
// folder is removed with the OpenBag.

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "slamprep/eval/formats/bag_storage.hpp"
#include "slamprep/eval/formats/rosbag2.hpp"

namespace slamprep::eval {

class OpenBag {
 public:
  /// `scratch_parent`: where the scratch folder goes (the import's spill directory, on the
  /// output's disk); empty: the system's temp directory.
  OpenBag(Rosbag2Bag bag, const std::filesystem::path& scratch_parent);
  ~OpenBag();
  OpenBag(const OpenBag&) = delete;
  OpenBag& operator=(const OpenBag&) = delete;

  const Rosbag2Bag& bag() const { return bag_; }
  std::vector<BagStorage*> storages() const;
  /// The input file each storage was read from (its errors name the copy when one was made).
  const std::vector<std::string>& names() const { return names_; }
  /// What opening did that the user should know ("2 files unpacked (FILE zstd) ...").
  const std::vector<std::string>& notes() const { return notes_; }

 private:
  void close();  ///< the storages closed, the scratch folder removed
  std::filesystem::path scratch(const std::filesystem::path& parent);
  std::filesystem::path unpacked(const std::filesystem::path& file,
                                 const std::filesystem::path& parent);

  Rosbag2Bag bag_;
  std::filesystem::path scratch_;  ///< created when first needed
  std::vector<std::unique_ptr<ByteSource>> sources_;
  std::vector<std::unique_ptr<BagStorage>> storages_;
  std::vector<std::string> names_;
  std::vector<std::string> notes_;
};

}  // namespace slamprep::eval
