#pragma once
// One storage file of a ROS 2 bag, read message by message whatever its storage: MCAP (records
// pulled from a ByteSource, one chunk held) or sqlite3 (.db3, rows stepped through one at a
// time, opened read-only and immutable so nothing is ever written beside the user's bag).

#include <cstdint>
#include <filesystem>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "slamprep/eval/formats/bag_topics.hpp"
#include "slamprep/eval/formats/byte_source.hpp"
#include "slamprep/eval/formats/mcap.hpp"

namespace slamprep::eval {

/// One message as the importer needs it.
struct BagMessage {
  std::uint32_t topic_id = 0;     ///< the file's own id (MCAP channel id, sqlite topics.id)
  std::uint64_t log_time_ns = 0;  ///< when it was recorded (MCAP log_time, sqlite timestamp)
  std::uint64_t position = 0;     ///< MCAP: byte offset of the record or its chunk; sqlite: row id
  std::uint32_t sequence = 0;     ///< the message's index on its topic in this file
  std::string data;               ///< serialized (CDR), as stored (maybe zstd-compressed)
};

struct StorageTopic {
  std::string name;
  std::string type;      ///< normalType: "pkg/Type"
  std::string encoding;  ///< "cdr" for ROS 2
};

class BagStorage {
 public:
  virtual ~BagStorage() = default;
  virtual const std::string& name() const = 0;
  /// Every topic of the file, before any message is read.
  virtual BagTopics topics() = 0;
  /// The topic of a message next() returned.
  virtual const StorageTopic& topic(std::uint32_t id) const = 0;
  /// next() may leave out the messages of other topics (sqlite does; MCAP reads every record for
  /// its CRCs anyway). Call before the first next().
  virtual void select(const std::set<std::string>& topics) = 0;
  /// The next message (MCAP: file order; sqlite: timestamp order); false after the last. Throws
  /// InputError naming the file and where in it on corrupt data.
  virtual bool next(BagMessage& m) = 0;
  /// "offset N" or "row N": where a message's position is, for errors.
  virtual std::string positionText(std::uint64_t position) const = 0;
  /// MCAP Metadata records (slamprep's nominal geometry); none for sqlite.
  virtual std::vector<McapMetadata> metadata() const { return {}; }
};

/// An MCAP file read from `source` (which must outlive the storage).
std::unique_ptr<BagStorage> openMcapStorage(ByteSource& source);

/// A rosbag2 sqlite3 file: SQLITE_OPEN_READONLY with the URI parameter immutable=1, so SQLite
/// creates no -wal, -shm or journal file and takes no lock. Tables topics(id, name, type,
/// serialization_format, ...) and messages(id, topic_id, timestamp, data); others (schema,
/// metadata) are ignored. Throws InputError naming the file when it is not an SQLite database
/// or lacks those tables. `immutable` false: a private copy (with its -wal) that SQLite may
/// recover into. Errors name `name` when given (a copy names its original).
std::unique_ptr<BagStorage> openSqliteStorage(const std::filesystem::path& file,
                                              bool immutable = true, const std::string& name = "");

}  // namespace slamprep::eval
