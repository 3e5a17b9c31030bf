#include <algorithm>
#include <cstring>

#include "slamprep/core/error.hpp"
#include "slamprep/eval/formats/mcap.hpp"
#include "slamprep/eval/formats/mcap_records.hpp"

namespace slamprep::eval {
using namespace mcap;
namespace {

// Footer record: opcode + length + summary_start, summary_offset_start, summary_crc.
constexpr std::uint64_t kFooterSize = 1 + 8 + 8 + 8 + 4;
constexpr std::size_t kBlock = std::size_t{1} << 16;  // bytes read at a time for CRCs

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

// map<string, string>: uint32 byte length, then key and value strings.
std::vector<std::pair<std::string, std::string>> parseMap(Cursor& c, const char* field) {
  const std::string_view map = c.bytes(c.le<std::uint32_t>(field), field);
  std::vector<std::pair<std::string, std::string>> out;
  std::size_t pos = 0;
  auto take = [&](const char* what) {
    if (map.size() - pos < 4) c.fail(std::string(field) + ": truncated " + what);
    std::uint32_t n;
    std::memcpy(&n, map.data() + pos, 4);
    pos += 4;
    if (n > map.size() - pos) c.fail(std::string(field) + ": " + what + " overruns the map");
    std::string s(map.substr(pos, n));
    pos += n;
    return s;
  };
  while (pos < map.size()) {
    std::string k = take("key");
    std::string v = take("value");
    out.emplace_back(std::move(k), std::move(v));
  }
  return out;
}

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
  ch.metadata = parseMap(c, "metadata");
  return ch;
}

}  // namespace

McapReader::McapReader(ByteSource& source) : source_(source), file_(source.name()) {
  size_ = source_.size();
  checkEnds();
  pos_ = kMagic.size();
  data_crc_ = crc32(kMagic);
}

std::string McapReader::where(std::uint64_t offset) const {
  return file_ + ": offset " + std::to_string(offset);
}

void McapReader::checkEnds() {
  if (size_ < kMagic.size() || (source_.read(0, kMagic.size(), block_), block_ != kMagic))
    throw InputError(where(0), "not an MCAP file (magic \\x89MCAP0\\r\\n missing)");
  if (source_.read(size_ - kMagic.size(), kMagic.size(), block_), block_ != kMagic)
    throw InputError(where(size_), "closing magic missing (truncated file?)");
  if (size_ < kMagic.size() * 2 + kFooterSize)
    throw InputError(file_, "too short for an MCAP footer (truncated)");
  footer_at_ = size_ - kMagic.size() - kFooterSize;
  source_.read(footer_at_, kFooterSize, block_);
  Cursor c(block_, file_, footer_at_, "Footer");
  if (c.le<std::uint8_t>("opcode") != kFooter || c.le<std::uint64_t>("length") != 20)
    c.fail("no footer record before the closing magic (truncated file?)");
  summary_start_ = c.le<std::uint64_t>("summary_start");
  summary_offset_start_ = c.le<std::uint64_t>("summary_offset_start");
  const auto summary_crc = c.le<std::uint32_t>("summary_crc");
  if (summary_start_ == 0) return;
  if (summary_start_ > footer_at_) c.fail("summary_start points past the footer");
  if (summary_offset_start_ != 0 &&
      (summary_offset_start_ < summary_start_ || summary_offset_start_ > footer_at_))
    c.fail("summary_offset_start outside the summary section");
  if (summary_crc == 0) return;
  // The summary CRC covers the summary section through the footer's summary_start and
  // summary_offset_start fields, read a block at a time.
  std::uint32_t crc = 0;
  const std::uint64_t crc_end = size_ - kMagic.size() - 4;
  for (std::uint64_t at = summary_start_; at < crc_end; at += kBlock) {
    source_.read(at, static_cast<std::size_t>(std::min<std::uint64_t>(kBlock, crc_end - at)),
                 block_);
    crc = crc32(block_, crc);
  }
  if (crc != summary_crc) c.fail("summary_crc does not match the summary section");
}

bool McapReader::next(McapMessage& m) {
  while (true) {
    if (chunk_pos_ < chunk_.size()) {
      if (chunkRecord(m)) return true;
    } else if (done_) {
      return false;
    } else if (dataRecord(m)) {
      return true;
    }
  }
}

void McapReader::addSchema(McapSchema s, std::uint64_t offset) {
  auto [it, inserted] = schemas_.emplace(s.id, s);
  if (!inserted && (it->second.name != s.name || it->second.data != s.data))
    throw InputError(where(offset),
                     "Schema: id " + std::to_string(s.id) + ": redefined with different content");
}

void McapReader::addChannel(McapChannel ch, std::uint64_t offset) {
  if (ch.schema_id != 0 && !schemas_.count(ch.schema_id))
    throw InputError(where(offset), "Channel: schema_id " + std::to_string(ch.schema_id) +
                                        " of topic \"" + ch.topic +
                                        "\" was not defined before the channel");
  auto [it, inserted] = channels_.emplace(ch.id, ch);
  if (!inserted && (it->second.topic != ch.topic || it->second.schema_id != ch.schema_id))
    throw InputError(where(offset),
                     "Channel: id " + std::to_string(ch.id) + ": redefined with different content");
}

namespace {

void readMessage(Cursor& c, std::uint64_t offset,
                 const std::map<std::uint16_t, McapChannel>& channels, McapMessage& m) {
  m.channel_id = c.le<std::uint16_t>("channel_id");
  m.sequence = c.le<std::uint32_t>("sequence");
  m.log_time_ns = c.le<std::uint64_t>("log_time");
  m.publish_time_ns = c.le<std::uint64_t>("publish_time");
  m.data.assign(c.rest());
  m.file_offset = offset;
  if (!channels.count(m.channel_id))
    c.fail("channel_id " + std::to_string(m.channel_id) + " was not defined before the message");
}

}  // namespace

// One record inside the open chunk: only Schema, Channel and Message may appear there.
bool McapReader::chunkRecord(McapMessage& m) {
  Cursor head(chunk_.substr(chunk_pos_), file_, chunk_offset_, "Chunk");
  const auto op = head.le<std::uint8_t>("records.opcode");
  const auto len = head.le<std::uint64_t>("records.length");
  Cursor c(head.bytes(len, "records.body"), file_, chunk_offset_, opName(op));
  chunk_pos_ += 9 + len;
  if (op == kSchema) {
    addSchema(parseSchema(c), chunk_offset_);
  } else if (op == kChannel) {
    addChannel(parseChannel(c), chunk_offset_);
  } else if (op == kMessage) {
    readMessage(c, chunk_offset_, channels_, m);
    return true;
  } else {
    c.fail("record not allowed inside a chunk");
  }
  return false;
}

void McapReader::readChunk(std::uint64_t offset) {
  Cursor c(record_, file_, offset + 9, "Chunk");
  c.le<std::uint64_t>("message_start_time");
  c.le<std::uint64_t>("message_end_time");
  const auto uncompressed_size = c.le<std::uint64_t>("uncompressed_size");
  const auto uncompressed_crc = c.le<std::uint32_t>("uncompressed_crc");
  const std::string compression = c.string("compression");
  const std::string_view records = c.bytes(c.le<std::uint64_t>("records"), "records");
  chunk_ = records;
  if (!compression.empty()) {
    unpacked_ = decompressChunk(compression, records, uncompressed_size, where(offset) + ": Chunk");
    chunk_ = unpacked_;
  }
  if (uncompressed_size != chunk_.size())
    c.fail("uncompressed_size " + std::to_string(uncompressed_size) + " but the records hold " +
           std::to_string(chunk_.size()) + " bytes");
  if (uncompressed_crc != 0 && crc32(chunk_) != uncompressed_crc)
    c.fail("uncompressed_crc does not match the records (corrupt chunk)");
  chunk_pos_ = 0;
  chunk_offset_ = offset;
  ++chunk_count_;
}

// A record the reader does not use: read only for the data-section CRC, a block at a time.
void McapReader::skipBody(std::uint64_t offset, std::uint64_t length) {
  for (std::uint64_t at = offset; at < offset + length; at += kBlock) {
    source_.read(at,
                 static_cast<std::size_t>(std::min<std::uint64_t>(kBlock, offset + length - at)),
                 block_);
    data_crc_ = crc32(block_, data_crc_);
  }
}

// Header, Schema, Channel and Metadata records (in record_, read at `at`): what later records
// refer to or the file says of itself. Other records are left to the caller.
void McapReader::applyDefinition(std::uint8_t op, std::uint64_t at) {
  Cursor c(record_, file_, at + 9, opName(op));
  switch (op) {
    case kHeader:
      profile_ = c.string("profile");
      library_ = c.string("library");
      break;
    case kSchema:
      addSchema(parseSchema(c), at);
      break;
    case kChannel:
      addChannel(parseChannel(c), at);
      break;
    case kMetadata: {
      McapMetadata meta;
      meta.name = c.string("name");
      meta.entries = parseMap(c, "metadata");
      metadata_.push_back(std::move(meta));
      break;
    }
    default:
      break;
  }
}

// One record of the data section, at pos_. True when it was a message (written to `m`).
bool McapReader::dataRecord(McapMessage& m) {
  const std::uint64_t at = pos_, room = size_ - kMagic.size() - at;
  if (room < 9) throw InputError(where(at), "record: truncated record header");
  std::string head;
  source_.read(at, 9, head);
  Cursor h(head, file_, at, "record");
  const auto op = h.le<std::uint8_t>("opcode");
  const auto len = h.le<std::uint64_t>("length");
  if (len > room - 9)
    throw InputError(where(at + 9), std::string(opName(op)) + ": body: needs " +
                                        std::to_string(len) + " bytes, only " +
                                        std::to_string(room - 9) +
                                        " left in the file (truncated or corrupt)");
  if (!header_seen_ && op != kHeader)
    throw InputError(where(at + 9),
                     std::string(opName(op)) + ": the first record must be a Header");
  header_seen_ = true;
  pos_ = at + 9 + len;
  if (op == kFooter) {  // a file without DataEnd (allowed by older writers)
    done_ = true;
    return false;
  }
  const bool parsed = op == kHeader || op == kSchema || op == kChannel || op == kMessage ||
                      op == kChunk || op == kMetadata || op == kDataEnd;
  if (!parsed) {  // index, statistics, attachment records: not needed to read the data
    data_crc_ = crc32(head, data_crc_);
    skipBody(at + 9, len);
    return false;
  }
  source_.read(at + 9, static_cast<std::size_t>(len), record_);
  Cursor c(record_, file_, at + 9, opName(op));
  if (op == kDataEnd) {
    const auto crc = c.le<std::uint32_t>("data_section_crc");
    if (crc != 0 && crc != data_crc_)
      c.fail("data_section_crc does not match the data section (corrupt file)");
    data_crc_checked_ = crc != 0;
    done_ = true;
    return false;
  }
  applyDefinition(op, at);
  data_crc_ = crc32(record_, crc32(head, data_crc_));
  if (op == kMessage) {
    readMessage(c, at, channels_, m);
    return true;
  }
  if (op == kChunk) readChunk(at);
  return false;
}

std::optional<McapSummary> McapReader::summary() {
  if (summary_start_ == 0) return std::nullopt;
  McapSummary s;
  const std::uint64_t end = summary_offset_start_ ? summary_offset_start_ : footer_at_;
  std::string head, body;
  for (std::uint64_t at = summary_start_; at < end;) {
    if (end - at < 9) throw InputError(where(at), "summary: truncated record header");
    source_.read(at, 9, head);
    Cursor h(head, file_, at, "summary record");
    const auto op = h.le<std::uint8_t>("opcode");
    const auto len = h.le<std::uint64_t>("length");
    if (len > end - at - 9) h.fail("length overruns the summary section");
    if (op == kSchema || op == kChannel) {
      source_.read(at + 9, static_cast<std::size_t>(len), body);
      Cursor c(body, file_, at + 9, opName(op));
      if (op == kSchema) {
        McapSchema schema = parseSchema(c);
        s.schemas.emplace(schema.id, std::move(schema));
      } else {
        McapChannel channel = parseChannel(c);
        s.channels.emplace(channel.id, std::move(channel));
      }
    }
    at += 9 + len;
  }
  return s;
}

McapFile readMcap(std::string_view bytes, const std::string& file) {
  const auto source = memorySource(bytes, file);
  McapReader reader(*source);
  McapFile f;
  McapMessage m;
  while (reader.next(m)) f.messages.push_back(m);
  f.profile = reader.profile();
  f.library = reader.library();
  f.schemas = reader.schemas();
  f.channels = reader.channels();
  f.metadata = reader.metadata();
  f.chunk_count = reader.chunkCount();
  f.has_summary = reader.hasSummary();
  f.data_crc_checked = reader.dataCrcChecked();
  return f;
}

}  // namespace slamprep::eval
