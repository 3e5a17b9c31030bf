#include <cstring>

#include "core/error.hpp"
#include "eval/formats/decompress.hpp"
#include "eval/formats/mcap.hpp"
#include "eval/formats/mcap_records.hpp"

namespace slamprep::eval {
using namespace mcap;
namespace {

const char* opName(std::uint8_t op) {
  static const char* names[] = {"Reserved",   "Header",        "Footer",          "Schema",
                                "Channel",    "Message",       "Chunk",           "MessageIndex",
                                "ChunkIndex", "Attachment",    "AttachmentIndex", "Statistics",
                                "Metadata",   "MetadataIndex", "SummaryOffset",   "DataEnd"};
  return op < 16 ? names[op] : "unknown";
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

McapFile readMcap(std::string_view bytes, const std::string& file) {
  Reader reader{bytes, file, {}};
  reader.read();
  return std::move(reader.result);
}

}  // namespace slamprep::eval
