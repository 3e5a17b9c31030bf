#include <array>
#include <cstring>

#include "slamprep/eval/formats/mcap.hpp"
#include "slamprep/eval/formats/mcap_records.hpp"

namespace slamprep::eval {
using namespace mcap;
namespace {

// ---- little-endian primitives (MCAP is little endian throughout) ----

template <typename T>
void putLe(std::string& out, T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));  // host is little endian (static_assert in cdr.cpp)
  out.append(b, sizeof(T));
}
void putString(std::string& out, std::string_view s) {
  putLe<std::uint32_t>(out, static_cast<std::uint32_t>(s.size()));
  out.append(s);
}
void putRecord(std::string& out, std::uint8_t op, std::string_view body) {
  out.push_back(static_cast<char>(op));
  putLe<std::uint64_t>(out, body.size());
  out.append(body);
}

std::string schemaBody(const McapSchema& s) {
  std::string b;
  putLe<std::uint16_t>(b, s.id);
  putString(b, s.name);
  putString(b, s.encoding);
  putString(b, s.data);  // bytes: uint32 length prefix, like a string
  return b;
}

std::string channelBody(const McapChannel& c) {
  std::string b, map;
  putLe<std::uint16_t>(b, c.id);
  putLe<std::uint16_t>(b, c.schema_id);
  putString(b, c.topic);
  putString(b, c.message_encoding);
  for (const auto& [k, v] : c.metadata) {
    putString(map, k);
    putString(map, v);
  }
  putString(b, map);  // map: uint32 byte length, then the entries
  return b;
}

}  // namespace

McapWriter::McapWriter(McapWriterParams params, std::ostream* out)
    : params_(std::move(params)), stream_(out) {
  out_.append(kMagic);
  std::string header;
  putString(header, params_.profile);
  putString(header, params_.library);
  putRecord(out_, kHeader, header);
}

std::uint16_t McapWriter::addSchema(std::string name, std::string encoding, std::string data) {
  flushChunk();
  McapSchema s{static_cast<std::uint16_t>(schemas_.size() + 1), std::move(name),
               std::move(encoding), std::move(data)};
  putRecord(out_, kSchema, schemaBody(s));
  schemas_.push_back(std::move(s));
  return schemas_.back().id;
}

std::uint16_t McapWriter::addChannel(std::uint16_t schema_id, std::string topic,
                                     std::string message_encoding,
                                     std::vector<std::pair<std::string, std::string>> metadata) {
  flushChunk();
  McapChannel c{static_cast<std::uint16_t>(channels_.size()), schema_id, std::move(topic),
                std::move(message_encoding), std::move(metadata)};
  putRecord(out_, kChannel, channelBody(c));
  channels_.push_back(std::move(c));
  channel_counts_[channels_.back().id] = 0;
  return channels_.back().id;
}

void McapWriter::addMetadata(std::string name,
                             std::vector<std::pair<std::string, std::string>> entries) {
  flushChunk();
  std::string body, map;
  putString(body, name);
  for (const auto& [k, v] : entries) {
    putString(map, k);
    putString(map, v);
  }
  putString(body, map);
  metadata_indexes_.push_back({position(), 9 + body.size(), std::move(name)});
  putRecord(out_, kMetadata, body);
}

void McapWriter::addMessage(std::uint16_t channel_id, std::uint64_t log_time_ns,
                            std::uint64_t publish_time_ns, std::string_view data) {
  std::string body;
  putLe<std::uint16_t>(body, channel_id);
  putLe<std::uint32_t>(body, static_cast<std::uint32_t>(channel_counts_[channel_id]++));
  putLe<std::uint64_t>(body, log_time_ns);
  putLe<std::uint64_t>(body, publish_time_ns);
  body.append(data);

  start_ns_ = message_count_ == 0 ? log_time_ns : std::min(start_ns_, log_time_ns);
  end_ns_ = message_count_ == 0 ? log_time_ns : std::max(end_ns_, log_time_ns);
  ++message_count_;

  if (params_.chunk_size_bytes == 0) {
    putRecord(out_, kMessage, body);
    return;
  }
  const bool empty = chunk_index_.empty();
  chunk_start_ns_ = empty ? log_time_ns : std::min(chunk_start_ns_, log_time_ns);
  chunk_end_ns_ = empty ? log_time_ns : std::max(chunk_end_ns_, log_time_ns);
  chunk_index_[channel_id].emplace_back(log_time_ns, chunk_.size());
  putRecord(chunk_, kMessage, body);
  if (chunk_.size() >= params_.chunk_size_bytes) flushChunk();
}

void McapWriter::flushOut() {
  if (!stream_ || out_.empty()) return;
  stream_->write(out_.data(), static_cast<std::streamsize>(out_.size()));
  written_crc_ = crc32(out_, written_crc_);
  written_ += out_.size();
  out_.clear();
}

void McapWriter::flushChunk() {
  if (chunk_index_.empty()) return;
  ChunkIndexEntry entry;
  entry.start_ns = chunk_start_ns_;
  entry.end_ns = chunk_end_ns_;
  entry.offset = position();
  const std::string packed = compressChunk(params_.compression, chunk_);
  entry.compressed_size = packed.size();
  entry.uncompressed_size = chunk_.size();
  std::string body;
  putLe<std::uint64_t>(body, chunk_start_ns_);
  putLe<std::uint64_t>(body, chunk_end_ns_);
  putLe<std::uint64_t>(body, chunk_.size());  // uncompressed_size
  putLe<std::uint32_t>(body, crc32(chunk_));  // uncompressed_crc
  putString(body, mcapCompressionName(params_.compression));
  putLe<std::uint64_t>(body, packed.size());  // records: uint64 length prefix
  body.append(packed);
  putRecord(out_, kChunk, body);
  entry.length = position() - entry.offset;
  writeMessageIndexes(entry);
  chunk_indexes_.push_back(std::move(entry));
  chunk_.clear();
  chunk_index_.clear();
  flushOut();
}

void McapWriter::writeMessageIndexes(ChunkIndexEntry& entry) {
  const std::uint64_t index_start = position();
  for (const auto& [channel, entries] : chunk_index_) {  // std::map: sorted by channel id
    entry.index_offsets[channel] = position();
    std::string index;
    putLe<std::uint16_t>(index, channel);
    putLe<std::uint32_t>(index, static_cast<std::uint32_t>(entries.size() * 16));
    for (const auto& [t, offset] : entries) {
      putLe<std::uint64_t>(index, t);
      putLe<std::uint64_t>(index, offset);
    }
    putRecord(out_, kMessageIndex, index);
  }
  entry.index_length = position() - index_start;
}

std::string McapWriter::statisticsBody() const {
  std::string b, counts;
  putLe<std::uint64_t>(b, message_count_);
  putLe<std::uint16_t>(b, static_cast<std::uint16_t>(schemas_.size()));
  putLe<std::uint32_t>(b, static_cast<std::uint32_t>(channels_.size()));
  putLe<std::uint32_t>(b, 0);  // attachment_count
  putLe<std::uint32_t>(b, static_cast<std::uint32_t>(metadata_indexes_.size()));
  putLe<std::uint32_t>(b, static_cast<std::uint32_t>(chunk_indexes_.size()));
  putLe<std::uint64_t>(b, start_ns_);
  putLe<std::uint64_t>(b, end_ns_);
  for (const auto& [channel, n] : channel_counts_) {
    putLe<std::uint16_t>(counts, channel);
    putLe<std::uint64_t>(counts, n);
  }
  putString(b, counts);
  return b;
}

std::string McapWriter::chunkIndexBody(const ChunkIndexEntry& e) const {
  std::string b, offsets;
  putLe<std::uint64_t>(b, e.start_ns);
  putLe<std::uint64_t>(b, e.end_ns);
  putLe<std::uint64_t>(b, e.offset);
  putLe<std::uint64_t>(b, e.length);
  for (const auto& [channel, offset] : e.index_offsets) {
    putLe<std::uint16_t>(offsets, channel);
    putLe<std::uint64_t>(offsets, offset);
  }
  putString(b, offsets);
  putLe<std::uint64_t>(b, e.index_length);
  putString(b, mcapCompressionName(params_.compression));
  putLe<std::uint64_t>(b, e.compressed_size);
  putLe<std::uint64_t>(b, e.uncompressed_size);
  return b;
}

std::string McapWriter::finish() {
  flushChunk();
  std::string data_end;
  putLe<std::uint32_t>(data_end, crc32(out_, written_crc_));  // the whole data section
  putRecord(out_, kDataEnd, data_end);
  flushOut();

  const std::uint64_t summary_start = position();
  const std::size_t summary_at = out_.size();        // where the summary starts in out_
  std::vector<std::array<std::uint64_t, 3>> groups;  // opcode, start, length
  auto group = [&](std::uint8_t op, auto&& write) {
    const std::uint64_t start = position();
    write();
    if (position() > start) groups.push_back({op, start, position() - start});
  };
  group(kSchema, [&] {
    for (const auto& s : schemas_) putRecord(out_, kSchema, schemaBody(s));
  });
  group(kChannel, [&] {
    for (const auto& c : channels_) putRecord(out_, kChannel, channelBody(c));
  });
  group(kStatistics, [&] { putRecord(out_, kStatistics, statisticsBody()); });
  group(kMetadataIndex, [&] {
    for (const auto& m : metadata_indexes_) {
      std::string b;
      putLe<std::uint64_t>(b, m.offset);
      putLe<std::uint64_t>(b, m.length);
      putString(b, m.name);
      putRecord(out_, kMetadataIndex, b);
    }
  });
  group(kChunkIndex, [&] {
    for (const auto& e : chunk_indexes_) putRecord(out_, kChunkIndex, chunkIndexBody(e));
  });
  const std::uint64_t summary_offset_start = position();
  for (const auto& [op, start, length] : groups) {
    std::string b;
    b.push_back(static_cast<char>(op));
    putLe<std::uint64_t>(b, start);
    putLe<std::uint64_t>(b, length);
    putRecord(out_, kSummaryOffset, b);
  }
  // Footer: the summary CRC covers the summary section through summary_offset_start.
  out_.push_back(static_cast<char>(kFooter));
  putLe<std::uint64_t>(out_, 20);
  putLe<std::uint64_t>(out_, summary_start);
  putLe<std::uint64_t>(out_, summary_offset_start);
  putLe<std::uint32_t>(out_, crc32(std::string_view(out_).substr(summary_at)));
  out_.append(kMagic);
  flushOut();
  std::string result = std::move(out_);
  out_.clear();
  return result;
}

}  // namespace slamprep::eval
