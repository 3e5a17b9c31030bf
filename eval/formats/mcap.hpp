#pragma once
// MCAP container (https://mcap.dev/spec, format version 0 "MCAP0"), written and read from the
// specification: magic, Header, data section (Schema, Channel, Message records, optionally
// grouped in uncompressed Chunks followed by their MessageIndex records), DataEnd with the data
// section CRC-32, a summary section (Schema, Channel, Statistics and ChunkIndex records), Summary
// Offset records, Footer with the summary CRC-32, magic.

#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "eval/formats/crc32.hpp"

namespace slamprep::eval {

struct McapSchema {
  std::uint16_t id = 0;
  std::string name;      ///< e.g. "sensor_msgs/msg/LaserScan"
  std::string encoding;  ///< e.g. "ros2msg"
  std::string data;      ///< the schema text
};

struct McapChannel {
  std::uint16_t id = 0;
  std::uint16_t schema_id = 0;  ///< 0 = no schema
  std::string topic;
  std::string message_encoding;  ///< e.g. "cdr"
  std::vector<std::pair<std::string, std::string>> metadata;
};

struct McapMessage {
  std::uint16_t channel_id = 0;
  std::uint32_t sequence = 0;
  std::uint64_t log_time_ns = 0;
  std::uint64_t publish_time_ns = 0;
  std::string data;
  std::uint64_t file_offset = 0;  ///< where the record starts (reader only; inside a chunk: the
                                  ///< chunk record's offset)
};

struct McapWriterParams {
  std::string profile = "ros2";      ///< Header.profile
  std::string library = "slamprep";  ///< Header.library
  /// Messages are grouped in chunks of about this many bytes; 0 writes no chunks (every
  /// message directly in the data section, no message or chunk indexes).
  std::size_t chunk_size_bytes = 1 << 20;
};

/// Builds an MCAP file in memory. Schemas and channels first (each written to the data section
/// when added, and repeated in the summary), then messages in the order they are added.
class McapWriter {
 public:
  explicit McapWriter(McapWriterParams params = {});

  std::uint16_t addSchema(std::string name, std::string encoding, std::string data);
  std::uint16_t addChannel(std::uint16_t schema_id, std::string topic, std::string message_encoding,
                           std::vector<std::pair<std::string, std::string>> metadata = {});
  /// The sequence number counts the channel's messages from 0.
  void addMessage(std::uint16_t channel_id, std::uint64_t log_time_ns,
                  std::uint64_t publish_time_ns, std::string_view data);

  /// Closes the file and returns its bytes. The writer is empty afterwards.
  std::string finish();

 private:
  struct ChunkIndexEntry {
    std::uint64_t start_ns = 0, end_ns = 0, offset = 0, length = 0, index_length = 0;
    std::map<std::uint16_t, std::uint64_t> index_offsets;
    std::uint64_t size = 0;
  };
  void flushChunk();
  void writeMessageIndexes(ChunkIndexEntry& entry);  ///< of the open chunk, just written
  std::string statisticsBody() const;
  static std::string chunkIndexBody(const ChunkIndexEntry& entry);

  McapWriterParams params_;
  std::string out_;
  std::vector<McapSchema> schemas_;
  std::vector<McapChannel> channels_;
  std::map<std::uint16_t, std::uint64_t> channel_counts_;
  std::uint64_t message_count_ = 0, start_ns_ = 0, end_ns_ = 0;
  // The open chunk.
  std::string chunk_;
  std::uint64_t chunk_start_ns_ = 0, chunk_end_ns_ = 0;
  std::map<std::uint16_t, std::vector<std::pair<std::uint64_t, std::uint64_t>>> chunk_index_;
  std::vector<ChunkIndexEntry> chunk_indexes_;
};

/// What readMcap found: every message in file order, and the records that describe them.
struct McapFile {
  std::string profile;
  std::string library;
  std::map<std::uint16_t, McapSchema> schemas;
  std::map<std::uint16_t, McapChannel> channels;
  std::vector<McapMessage> messages;
  std::size_t chunk_count = 0;
  bool has_summary = false;       ///< a summary section was present (its CRC was checked)
  bool data_crc_checked = false;  ///< DataEnd held a non-zero CRC and it matched
};

/// Reads a whole MCAP file (`file` names it in errors). Linear read: every record is visited in
/// order, chunks are unpacked (compression "", "zstd" or "lz4": eval/formats/decompress.hpp),
/// every non-zero CRC is verified. Throws InputError naming the file, the byte offset of the
/// record and the field on any malformed or truncated input.
McapFile readMcap(std::string_view bytes, const std::string& file);

}  // namespace slamprep::eval
