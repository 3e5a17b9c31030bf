#include "eval/formats/mcap.hpp"

#include <array>
#include <cstring>
#include <limits>

#include "core/error.hpp"
#include "eval/formats/decompress.hpp"

namespace slamprep::eval {
namespace {

constexpr std::string_view kMagic("\x89MCAP0\r\n", 8);

enum Op : std::uint8_t {
  kHeader = 0x01,
  kFooter = 0x02,
  kSchema = 0x03,
  kChannel = 0x04,
  kMessage = 0x05,
  kChunk = 0x06,
  kMessageIndex = 0x07,
  kChunkIndex = 0x08,
  kAttachment = 0x09,
  kAttachmentIndex = 0x0A,
  kStatistics = 0x0B,
  kMetadata = 0x0C,
  kMetadataIndex = 0x0D,
  kSummaryOffset = 0x0E,
  kDataEnd = 0x0F,
};

const char* opName(std::uint8_t op) {
  static const char* names[] = {"Reserved",   "Header",        "Footer",          "Schema",
                                "Channel",    "Message",       "Chunk",           "MessageIndex",
                                "ChunkIndex", "Attachment",    "AttachmentIndex", "Statistics",
                                "Metadata",   "MetadataIndex", "SummaryOffset",   "DataEnd"};
  return op < 16 ? names[op] : "unknown";
}

const std::array<std::uint32_t, 256>& crcTable() {
  static const std::array<std::uint32_t, 256> table = [] {
    std::array<std::uint32_t, 256> t{};
    for (std::uint32_t i = 0; i < 256; ++i) {
      std::uint32_t c = i;
      for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      t[i] = c;
    }
    return t;
  }();
  return table;
}

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

// ---- bounds-checked reader over one record body ----

class Cursor {
 public:
  Cursor(std::string_view data, const std::string& file, std::uint64_t base, const char* record)
      : data_(data), file_(file), base_(base), record_(record) {}

  template <typename T>
  T le(const char* field) {
    need(sizeof(T), field);
    T v;
    std::memcpy(&v, data_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return v;
  }
  std::string_view bytes(std::uint64_t n, const char* field) {
    need(n, field);
    const auto s = data_.substr(pos_, n);
    pos_ += n;
    return s;
  }
  std::string string(const char* field) {
    return std::string(bytes(le<std::uint32_t>(field), field));
  }
  std::string_view rest() { return bytes(data_.size() - pos_, "data"); }
  bool done() const { return pos_ == data_.size(); }
  std::size_t left() const { return data_.size() - pos_; }

  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(file_ + ": offset " + std::to_string(base_ + pos_),
                     std::string(record_) + ": " + what);
  }

 private:
  void need(std::uint64_t n, const char* field) const {
    if (n > data_.size() - pos_)
      fail(std::string(field) + ": needs " + std::to_string(n) + " bytes, only " +
           std::to_string(data_.size() - pos_) + " left in the record (truncated or corrupt)");
  }
  std::string_view data_;
  const std::string& file_;
  std::uint64_t base_;
  std::size_t pos_ = 0;
  const char* record_;
};

McapSchema parseSchema(Cursor& c) {
  McapSchema s;
  s.id = c.le<std::uint16_t>("id");
  s.name = c.string("name");
  s.encoding = c.string("encoding");
  s.data = c.string("data");
  if (s.id == 0) c.fail("id: 0 is reserved for \"no schema\"");
  return s;
}

McapChannel parseChannel(Cursor& c) {
  McapChannel ch;
  ch.id = c.le<std::uint16_t>("id");
  ch.schema_id = c.le<std::uint16_t>("schema_id");
  ch.topic = c.string("topic");
  ch.message_encoding = c.string("message_encoding");
  const std::uint32_t map_len = c.le<std::uint32_t>("metadata");
  const std::string_view map = c.bytes(map_len, "metadata");
  std::size_t pos = 0;
  auto take = [&](const char* what) {
    if (map.size() - pos < 4) c.fail(std::string("metadata: truncated ") + what);
    std::uint32_t n;
    std::memcpy(&n, map.data() + pos, 4);
    pos += 4;
    if (n > map.size() - pos) c.fail(std::string("metadata: ") + what + " overruns the map");
    std::string s(map.substr(pos, n));
    pos += n;
    return s;
  };
  while (pos < map.size()) {
    std::string k = take("key");
    std::string v = take("value");
    ch.metadata.emplace_back(std::move(k), std::move(v));
  }
  return ch;
}

struct Reader {
  std::string_view bytes;
  const std::string& file;
  McapFile result;

  void addSchema(McapSchema s, Cursor& c) {
    auto [it, inserted] = result.schemas.emplace(s.id, s);
    if (!inserted && (it->second.name != s.name || it->second.data != s.data))
      c.fail("id " + std::to_string(s.id) + ": redefined with different content");
  }
  void addChannel(McapChannel ch, Cursor& c) {
    if (ch.schema_id != 0 && !result.schemas.count(ch.schema_id))
      c.fail("schema_id " + std::to_string(ch.schema_id) + " of topic \"" + ch.topic +
             "\" was not defined before the channel");
    auto [it, inserted] = result.channels.emplace(ch.id, ch);
    if (!inserted && (it->second.topic != ch.topic || it->second.schema_id != ch.schema_id))
      c.fail("id " + std::to_string(ch.id) + ": redefined with different content");
  }
  void addMessage(Cursor& c, std::uint64_t offset) {
    McapMessage m;
    m.channel_id = c.le<std::uint16_t>("channel_id");
    m.sequence = c.le<std::uint32_t>("sequence");
    m.log_time_ns = c.le<std::uint64_t>("log_time");
    m.publish_time_ns = c.le<std::uint64_t>("publish_time");
    m.data = std::string(c.rest());
    m.file_offset = offset;
    if (!result.channels.count(m.channel_id))
      c.fail("channel_id " + std::to_string(m.channel_id) + " was not defined before the message");
    result.messages.push_back(std::move(m));
  }

  // Records inside a chunk: only Schema, Channel and Message may appear there.
  void readChunkRecords(std::string_view records, std::uint64_t chunk_offset) {
    std::size_t pos = 0;
    while (pos < records.size()) {
      Cursor head(records.substr(pos), file, chunk_offset, "Chunk");
      const auto op = head.le<std::uint8_t>("records.opcode");
      const auto len = head.le<std::uint64_t>("records.length");
      Cursor c(head.bytes(len, "records.body"), file, chunk_offset, opName(op));
      if (op == kSchema) {
        McapSchema s = parseSchema(c);
        addSchema(std::move(s), c);
      } else if (op == kChannel) {
        McapChannel ch = parseChannel(c);
        addChannel(std::move(ch), c);
      } else if (op == kMessage) {
        addMessage(c, chunk_offset);
      } else {
        c.fail("record not allowed inside a chunk");
      }
      pos += 9 + len;
    }
  }

  void readChunk(Cursor& c, std::uint64_t offset) {
    c.le<std::uint64_t>("message_start_time");
    c.le<std::uint64_t>("message_end_time");
    const auto uncompressed_size = c.le<std::uint64_t>("uncompressed_size");
    const auto uncompressed_crc = c.le<std::uint32_t>("uncompressed_crc");
    const std::string compression = c.string("compression");
    const auto records_len = c.le<std::uint64_t>("records");
    const std::string_view records = c.bytes(records_len, "records");
    std::string unpacked;
    std::string_view data = records;
    if (!compression.empty()) {
      unpacked = decompressChunk(compression, records, uncompressed_size,
                                 file + ": offset " + std::to_string(offset) + ": Chunk");
      data = unpacked;
    }
    if (uncompressed_size != data.size())
      c.fail("uncompressed_size " + std::to_string(uncompressed_size) + " but the records hold " +
             std::to_string(data.size()) + " bytes");
    if (uncompressed_crc != 0 && crc32(data) != uncompressed_crc)
      c.fail("uncompressed_crc does not match the records (corrupt chunk)");
    readChunkRecords(data, offset);
    ++result.chunk_count;
  }

  void checkFooter() {
    // Footer record: opcode + length + summary_start, summary_offset_start, summary_crc.
    constexpr std::size_t kFooterSize = 1 + 8 + 8 + 8 + 4;
    if (bytes.size() < kMagic.size() * 2 + kFooterSize)
      throw InputError(file, "too short for an MCAP footer (truncated)");
    const std::size_t footer_at = bytes.size() - kMagic.size() - kFooterSize;
    Cursor c(bytes.substr(footer_at, kFooterSize), file, footer_at, "Footer");
    if (c.le<std::uint8_t>("opcode") != kFooter || c.le<std::uint64_t>("length") != 20)
      c.fail("no footer record before the closing magic (truncated file?)");
    const auto summary_start = c.le<std::uint64_t>("summary_start");
    c.le<std::uint64_t>("summary_offset_start");
    const auto summary_crc = c.le<std::uint32_t>("summary_crc");
    if (summary_start == 0) return;
    if (summary_start > footer_at) c.fail("summary_start points past the footer");
    result.has_summary = true;
    const std::size_t crc_end = bytes.size() - kMagic.size() - 4;
    if (summary_crc != 0 &&
        crc32(bytes.substr(summary_start, crc_end - summary_start)) != summary_crc)
      c.fail("summary_crc does not match the summary section");
  }

  void read() {
    if (bytes.size() < kMagic.size() || bytes.substr(0, kMagic.size()) != kMagic)
      throw InputError(file + ": offset 0", "not an MCAP file (magic \\x89MCAP0\\r\\n missing)");
    if (bytes.substr(bytes.size() - kMagic.size()) != kMagic)
      throw InputError(file + ": offset " + std::to_string(bytes.size()),
                       "closing magic missing (truncated file?)");
    checkFooter();
    std::size_t pos = kMagic.size();
    bool first = true;
    while (true) {
      Cursor head(bytes.substr(pos), file, pos, "record");
      if (head.left() < 9) head.fail("truncated record header");
      const auto op = head.le<std::uint8_t>("opcode");
      const auto len = head.le<std::uint64_t>("length");
      Cursor c(head.bytes(len, "body"), file, pos + 9, opName(op));
      if (first && op != kHeader) c.fail("the first record must be a Header");
      first = false;
      switch (op) {
        case kHeader:
          result.profile = c.string("profile");
          result.library = c.string("library");
          break;
        case kSchema: {
          McapSchema s = parseSchema(c);
          addSchema(std::move(s), c);
          break;
        }
        case kChannel: {
          McapChannel ch = parseChannel(c);
          addChannel(std::move(ch), c);
          break;
        }
        case kMessage:
          addMessage(c, pos);
          break;
        case kChunk:
          readChunk(c, pos);
          break;
        case kDataEnd: {
          const auto crc = c.le<std::uint32_t>("data_section_crc");
          if (crc != 0 && crc32(bytes.substr(0, pos)) != crc)
            c.fail("data_section_crc does not match the data section (corrupt file)");
          result.data_crc_checked = crc != 0;
          return;
        }
        case kFooter:
          return;  // a file without DataEnd (allowed by older writers)
        default:
          break;  // index, statistics, attachment, metadata records: not needed to read data
      }
      pos += 9 + len;
    }
  }
};

}  // namespace

std::uint32_t crc32(std::string_view bytes, std::uint32_t crc) {
  const auto& table = crcTable();
  crc = ~crc;
  for (unsigned char b : bytes) crc = table[(crc ^ b) & 0xFF] ^ (crc >> 8);
  return ~crc;
}

McapWriter::McapWriter(McapWriterParams params) : params_(std::move(params)) {
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

void McapWriter::flushChunk() {
  if (chunk_index_.empty()) return;
  ChunkIndexEntry entry;
  entry.start_ns = chunk_start_ns_;
  entry.end_ns = chunk_end_ns_;
  entry.offset = out_.size();
  entry.size = chunk_.size();
  std::string body;
  putLe<std::uint64_t>(body, chunk_start_ns_);
  putLe<std::uint64_t>(body, chunk_end_ns_);
  putLe<std::uint64_t>(body, chunk_.size());  // uncompressed_size
  putLe<std::uint32_t>(body, crc32(chunk_));  // uncompressed_crc
  putString(body, "");                        // compression: none
  putLe<std::uint64_t>(body, chunk_.size());  // records: uint64 length prefix
  body.append(chunk_);
  putRecord(out_, kChunk, body);
  entry.length = out_.size() - entry.offset;

  const std::size_t index_start = out_.size();
  for (const auto& [channel, entries] : chunk_index_) {  // std::map: sorted by channel id
    entry.index_offsets[channel] = out_.size();
    std::string index;
    putLe<std::uint16_t>(index, channel);
    putLe<std::uint32_t>(index, static_cast<std::uint32_t>(entries.size() * 16));
    for (const auto& [t, offset] : entries) {
      putLe<std::uint64_t>(index, t);
      putLe<std::uint64_t>(index, offset);
    }
    putRecord(out_, kMessageIndex, index);
  }
  entry.index_length = out_.size() - index_start;
  chunk_indexes_.push_back(std::move(entry));
  chunk_.clear();
  chunk_index_.clear();
}

std::string McapWriter::finish() {
  flushChunk();
  std::string data_end;
  putLe<std::uint32_t>(data_end, crc32(out_));
  putRecord(out_, kDataEnd, data_end);

  const std::uint64_t summary_start = out_.size();
  std::vector<std::array<std::uint64_t, 3>> groups;  // opcode, start, length
  auto group = [&](std::uint8_t op, auto&& write) {
    const std::uint64_t start = out_.size();
    write();
    if (out_.size() > start) groups.push_back({op, start, out_.size() - start});
  };
  group(kSchema, [&] {
    for (const auto& s : schemas_) putRecord(out_, kSchema, schemaBody(s));
  });
  group(kChannel, [&] {
    for (const auto& c : channels_) putRecord(out_, kChannel, channelBody(c));
  });
  group(kStatistics, [&] {
    std::string b, counts;
    putLe<std::uint64_t>(b, message_count_);
    putLe<std::uint16_t>(b, static_cast<std::uint16_t>(schemas_.size()));
    putLe<std::uint32_t>(b, static_cast<std::uint32_t>(channels_.size()));
    putLe<std::uint32_t>(b, 0);  // attachment_count
    putLe<std::uint32_t>(b, 0);  // metadata_count
    putLe<std::uint32_t>(b, static_cast<std::uint32_t>(chunk_indexes_.size()));
    putLe<std::uint64_t>(b, start_ns_);
    putLe<std::uint64_t>(b, end_ns_);
    for (const auto& [channel, n] : channel_counts_) {
      putLe<std::uint16_t>(counts, channel);
      putLe<std::uint64_t>(counts, n);
    }
    putString(b, counts);
    putRecord(out_, kStatistics, b);
  });
  group(kChunkIndex, [&] {
    for (const auto& e : chunk_indexes_) {
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
      putString(b, "");                 // compression
      putLe<std::uint64_t>(b, e.size);  // compressed_size
      putLe<std::uint64_t>(b, e.size);  // uncompressed_size
      putRecord(out_, kChunkIndex, b);
    }
  });
  const std::uint64_t summary_offset_start = out_.size();
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
  putLe<std::uint32_t>(out_, crc32(std::string_view(out_).substr(summary_start)));
  out_.append(kMagic);
  std::string result = std::move(out_);
  out_.clear();
  return result;
}

McapFile readMcap(std::string_view bytes, const std::string& file) {
  Reader reader{bytes, file, {}};
  reader.read();
  return std::move(reader.result);
}

}  // namespace slamprep::eval
