#pragma once
// MCAP container (https://mcap.dev/spec, format version 0 "MCAP0"), written and read from the
// specification: magic, Header, data section (Schema, Channel, Metadata, Message records, the
// messages optionally grouped in Chunks, compressed or not, followed by their MessageIndex
// records), DataEnd with the data section CRC-32, a summary section (Schema, Channel, Statistics,
// MetadataIndex and ChunkIndex records), Summary Offset records, Footer with the summary CRC-32,
// magic.

#include <cstdint>
#include <map>
#include <optional>
#include <ostream>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "slamprep/eval/formats/byte_source.hpp"
#include "slamprep/eval/formats/compression.hpp"
#include "slamprep/eval/formats/crc32.hpp"

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
  /// Messages are grouped in chunks of about this many bytes (before compression); 0 writes no
  /// chunks (every message directly in the data section, no message or chunk indexes).
  std::size_t chunk_size_bytes = 1 << 20;
  Compression compression = Compression::kNone;  ///< of the chunks
};

/// Builds an MCAP file. Schemas, channels and metadata first (each written to the data section
/// when added, and repeated or indexed in the summary), then messages in the order they are
/// added. With an output stream the file goes out chunk by chunk (memory: one chunk and the
/// summary); without, finish() returns its bytes.
class McapWriter {
 public:
  explicit McapWriter(McapWriterParams params = {}, std::ostream* out = nullptr);

  std::uint16_t addSchema(std::string name, std::string encoding, std::string data);
  std::uint16_t addChannel(std::uint16_t schema_id, std::string topic, std::string message_encoding,
                           std::vector<std::pair<std::string, std::string>> metadata = {});
  /// A Metadata record (name, string pairs), indexed in the summary.
  void addMetadata(std::string name, std::vector<std::pair<std::string, std::string>> entries);
  /// The sequence number counts the channel's messages from 0.
  void addMessage(std::uint16_t channel_id, std::uint64_t log_time_ns,
                  std::uint64_t publish_time_ns, std::string_view data);

  /// Closes the file. Returns its bytes when written in memory (empty with an output stream);
  /// the writer is empty afterwards.
  std::string finish();

 private:
  struct ChunkIndexEntry {
    std::uint64_t start_ns = 0, end_ns = 0, offset = 0, length = 0, index_length = 0;
    std::map<std::uint16_t, std::uint64_t> index_offsets;
    std::uint64_t compressed_size = 0, uncompressed_size = 0;
  };
  struct MetadataIndexEntry {
    std::uint64_t offset = 0, length = 0;
    std::string name;
  };
  std::uint64_t position() const { return written_ + out_.size(); }
  void flushOut();  ///< hands out_ to the stream (when there is one)
  void flushChunk();
  void writeMessageIndexes(ChunkIndexEntry& entry);  ///< of the open chunk, just written
  std::string statisticsBody() const;
  std::string chunkIndexBody(const ChunkIndexEntry& entry) const;

  McapWriterParams params_;
  std::ostream* stream_;
  std::string out_;                ///< bytes not yet handed to the stream
  std::uint64_t written_ = 0;      ///< bytes handed to the stream
  std::uint32_t written_crc_ = 0;  ///< CRC-32 of those bytes
  std::vector<McapSchema> schemas_;
  std::vector<McapChannel> channels_;
  std::vector<MetadataIndexEntry> metadata_indexes_;
  std::map<std::uint16_t, std::uint64_t> channel_counts_;
  std::uint64_t message_count_ = 0, start_ns_ = 0, end_ns_ = 0;
  // The open chunk.
  std::string chunk_;
  std::uint64_t chunk_start_ns_ = 0, chunk_end_ns_ = 0;
  std::map<std::uint16_t, std::vector<std::pair<std::uint64_t, std::uint64_t>>> chunk_index_;
  std::vector<ChunkIndexEntry> chunk_indexes_;
};

/// A Metadata record: a name and string pairs (slamprep writes its nominal geometry in one).
struct McapMetadata {
  std::string name;
  std::vector<std::pair<std::string, std::string>> entries;
};

/// The Schema and Channel records of a file's summary section.
struct McapSummary {
  std::map<std::uint16_t, McapSchema> schemas;
  std::map<std::uint16_t, McapChannel> channels;
};

/// Reads an MCAP file record by record from `source`: at most one chunk (compressed and
/// unpacked) and one record are held at a time, never the whole file. The constructor checks the
/// magic at both ends, the footer and the summary CRC; next() walks the data section in file
/// order. Chunks may be uncompressed, "zstd" or "lz4" (eval/formats/compression.hpp); every
/// non-zero CRC is verified, the data section's when DataEnd is reached. Errors are InputError
/// naming the file, the byte offset of the record and the field.
class McapReader {
 public:
  explicit McapReader(ByteSource& source);

  /// The next message in file order; false after the data section. `m` is overwritten (its
  /// string's capacity reused).
  bool next(McapMessage& m);
  /// The schemas and channels of the summary section (read when called; nullopt without one):
  /// the topics of a file before any message is read.
  std::optional<McapSummary> summary();

  /// Records of the data section seen so far.
  const std::map<std::uint16_t, McapSchema>& schemas() const { return schemas_; }
  const std::map<std::uint16_t, McapChannel>& channels() const { return channels_; }
  const std::vector<McapMetadata>& metadata() const { return metadata_; }
  const std::string& profile() const { return profile_; }
  const std::string& library() const { return library_; }
  std::size_t chunkCount() const { return chunk_count_; }
  bool hasSummary() const { return summary_start_ != 0; }
  /// DataEnd held a non-zero CRC and it matched (known once next() returned false).
  bool dataCrcChecked() const { return data_crc_checked_; }

 private:
  void checkEnds();
  bool dataRecord(McapMessage& m);
  void applyDefinition(std::uint8_t op, std::uint64_t at);
  bool chunkRecord(McapMessage& m);
  void readChunk(std::uint64_t offset);
  void skipBody(std::uint64_t offset, std::uint64_t length);
  void addSchema(McapSchema s, std::uint64_t offset);
  void addChannel(McapChannel ch, std::uint64_t offset);
  std::string where(std::uint64_t offset) const;

  ByteSource& source_;
  const std::string& file_;
  std::uint64_t size_ = 0, pos_ = 0, footer_at_ = 0;
  std::uint64_t summary_start_ = 0, summary_offset_start_ = 0;
  bool header_seen_ = false, done_ = false, data_crc_checked_ = false;
  std::uint32_t data_crc_ = 0;  ///< running CRC of the data section read so far
  std::string record_, unpacked_, block_;
  std::string_view chunk_;  ///< records of the open chunk (in record_ or unpacked_)
  std::size_t chunk_pos_ = 0;
  std::uint64_t chunk_offset_ = 0;
  std::size_t chunk_count_ = 0;
  std::string profile_, library_;
  std::map<std::uint16_t, McapSchema> schemas_;
  std::map<std::uint16_t, McapChannel> channels_;
  std::vector<McapMetadata> metadata_;
};

/// What readMcap found: every message in file order, and the records that describe them.
struct McapFile {
  std::string profile;
  std::string library;
  std::map<std::uint16_t, McapSchema> schemas;
  std::map<std::uint16_t, McapChannel> channels;
  std::vector<McapMetadata> metadata;
  std::vector<McapMessage> messages;
  std::size_t chunk_count = 0;
  bool has_summary = false;       ///< a summary section was present (its CRC was checked)
  bool data_crc_checked = false;  ///< DataEnd held a non-zero CRC and it matched
};

/// Reads a whole MCAP file held in memory (`file` names it in errors) with McapReader, keeping
/// every message: for small files, tests and fuzzing.
McapFile readMcap(std::string_view bytes, const std::string& file);

}  // namespace slamprep::eval
