#pragma once
// rosbag2 sqlite3 bags made in code for the import tests, with the sqlite3 C API: the tables
// rosbag2 writes (topics, messages, and for newer bags schema and metadata), filled with the
// messages of an MCAP file (so the same messages can be imported from both storages), and the
// metadata.yaml of each rosbag2 version.

#include <sqlite3.h>

#include <filesystem>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "slamprep/eval/formats/compression.hpp"
#include "slamprep/eval/formats/mcap.hpp"

namespace slamprep::test {

struct SqliteBagParams {
  bool type_description_hash = false;  ///< Iron and later: a column of topics
  bool newer_tables = false;           ///< Jazzy: schema and metadata tables
  bool message_zstd = false;           ///< compression_mode MESSAGE: each blob a zstd frame
  bool wal = true;                     ///< journal_mode WAL, as rosbag2 records
  /// A recording that was not closed: the .db3 and its -wal copied here while the connection is
  /// open (no checkpoint: the messages are only in the WAL).
  std::filesystem::path copy_open_to;
};

inline void sqliteExec(sqlite3* db, const std::string& sql) {
  char* error = nullptr;
  if (sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &error) != SQLITE_OK) {
    const std::string what = error ? error : "?";
    sqlite3_free(error);
    throw std::runtime_error("sqlite: " + what + " in " + sql);
  }
}

inline std::string sqliteSchema(const SqliteBagParams& p) {
  std::string s =
      "CREATE TABLE schema(schema_version INTEGER PRIMARY KEY, ros_distro TEXT NOT NULL);"
      "INSERT INTO schema VALUES (3, 'jazzy');"
      "CREATE TABLE metadata(id INTEGER PRIMARY KEY, metadata_version INTEGER NOT NULL, "
      "metadata TEXT NOT NULL);";
  if (!p.newer_tables) s.clear();
  s += "CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL, "
       "serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL" +
       std::string(p.type_description_hash ? ", type_description_hash TEXT NOT NULL" : "") +
       ");"
       "CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL, timestamp "
       "INTEGER NOT NULL, data BLOB NOT NULL);"
       "CREATE INDEX timestamp_idx ON messages (timestamp ASC);";
  return s;
}

/// The messages of `mcap` whose log time `keep` accepts, into a new .db3 at `file` (topic ids
/// are the channel ids). Closed cleanly: no -wal or -shm is left.
inline void writeSqliteBag(const std::filesystem::path& file, const eval::McapFile& mcap,
                           const SqliteBagParams& p = {},
                           const std::function<bool(std::uint64_t)>& keep = nullptr) {
  std::filesystem::remove(file);
  sqlite3* db = nullptr;
  if (sqlite3_open(file.c_str(), &db) != SQLITE_OK) throw std::runtime_error("cannot create db");
  if (p.wal) sqliteExec(db, "PRAGMA journal_mode=WAL;");
  if (!p.copy_open_to.empty()) sqliteExec(db, "PRAGMA wal_autocheckpoint=0;");
  sqliteExec(db, sqliteSchema(p) + "BEGIN;");
  sqlite3_stmt* topic = nullptr;
  sqlite3_prepare_v2(db,
                     p.type_description_hash
                         ? "INSERT INTO topics VALUES (?, ?, ?, ?, '', 'RIHS01_00')"
                         : "INSERT INTO topics VALUES (?, ?, ?, ?, '')",
                     -1, &topic, nullptr);
  for (const auto& [id, ch] : mcap.channels) {
    const std::string type = mcap.schemas.at(ch.schema_id).name;
    sqlite3_bind_int(topic, 1, id);
    sqlite3_bind_text(topic, 2, ch.topic.c_str(), -1, SQLITE_TRANSIENT);
    sqlite3_bind_text(topic, 3, type.c_str(), -1, SQLITE_TRANSIENT);
    sqlite3_bind_text(topic, 4, ch.message_encoding.c_str(), -1, SQLITE_TRANSIENT);
    sqlite3_step(topic);
    sqlite3_reset(topic);
  }
  sqlite3_finalize(topic);
  sqlite3_stmt* message = nullptr;
  sqlite3_prepare_v2(db, "INSERT INTO messages (topic_id, timestamp, data) VALUES (?, ?, ?)", -1,
                     &message, nullptr);
  for (const auto& m : mcap.messages) {
    if (keep && !keep(m.log_time_ns)) continue;
    const std::string data =
        p.message_zstd ? eval::compressChunk(eval::Compression::kZstd, m.data) : m.data;
    sqlite3_bind_int(message, 1, m.channel_id);
    sqlite3_bind_int64(message, 2, static_cast<sqlite3_int64>(m.log_time_ns));
    sqlite3_bind_blob(message, 3, data.data(), static_cast<int>(data.size()), SQLITE_TRANSIENT);
    if (sqlite3_step(message) != SQLITE_DONE) throw std::runtime_error("insert failed");
    sqlite3_reset(message);
  }
  sqlite3_finalize(message);
  sqliteExec(db, "COMMIT;");
  if (!p.copy_open_to.empty()) {
    namespace fs = std::filesystem;
    fs::copy_file(file, p.copy_open_to, fs::copy_options::overwrite_existing);
    fs::copy_file(file.string() + "-wal", p.copy_open_to.string() + "-wal",
                  fs::copy_options::overwrite_existing);
  }
  sqlite3_close(db);
}

/// The QoS of a topic as rosbag2 writes it: a YAML string up to version 8, a list from 9.
inline std::string qosYaml(int version) {
  if (version >= 9)
    return "\n          - history: keep_last\n            depth: 10\n            reliability: "
           "reliable\n            durability: volatile\n            deadline:\n              "
           "sec: 9223372036\n              nsec: 854775807";
  return " \"- history: 3\\n  depth: 0\\n  reliability: 1\\n  durability: 2\\n  deadline:\\n    "
         "sec: 2147483647\\n    nsec: 4294967295\\n  avoid_ros_namespace_conventions: false\"";
}

/// A metadata.yaml as rosbag2 `version` writes it (fields added per version: files 5,
/// custom_data 6, type_description_hash 7, ros_distro 8, QoS as a list 9).
inline std::string metadataYaml(int version, const std::string& storage,
                                const std::vector<std::string>& files,
                                const std::string& compression_mode = "",
                                const std::string& compression_format = "") {
  std::string y = "rosbag2_bagfile_information:\n  version: " + std::to_string(version) +
                  "\n  storage_identifier: " + storage +
                  "\n  duration:\n    nanoseconds: 1\n"
                  "  starting_time:\n    nanoseconds_since_epoch: 1\n  message_count: 1\n"
                  "  topics_with_message_count:\n    - topic_metadata:\n        name: /scan\n"
                  "        type: sensor_msgs/msg/LaserScan\n        serialization_format: cdr\n"
                  "        offered_qos_profiles:" +
                  qosYaml(version) + "\n";
  if (version >= 7) y += "        type_description_hash: RIHS01_abcdef0123\n";
  y += "      message_count: 1\n  compression_format: \"" + compression_format +
       "\"\n  compression_mode: \"" + compression_mode + "\"\n  relative_file_paths:\n";
  for (const auto& f : files) y += "    - " + f + "\n";
  if (version >= 5) {
    y += "  files:\n";
    for (const auto& f : files)
      y += "    - path: " + f +
           "\n      starting_time:\n        nanoseconds_since_epoch: 1\n"
           "      duration:\n        nanoseconds: 1\n      message_count: 1\n";
  }
  if (version >= 6) y += "  custom_data: ~\n";
  if (version >= 8) y += "  ros_distro: " + std::string(version >= 9 ? "jazzy" : "iron") + "\n";
  return y;
}

}  // namespace slamprep::test
