// MCAP writer and reader from the specification: CRC, record layout, round trip, corruption.
#include "slamprep/eval/formats/mcap.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>

#include "slamprep/core/atomic_file.hpp"
#include "slamprep/core/error.hpp"
#include "slamprep/tests/support/scratch_dir.hpp"

namespace slamprep::eval {
namespace {

TEST(Crc32, MatchesTheStandardCheckValue) {
  // The CRC-32 check value of "123456789" (zlib, IEEE 802.3) is 0xCBF43926.
  EXPECT_EQ(crc32("123456789"), 0xCBF43926u);
  EXPECT_EQ(crc32(""), 0u);
  // Continuing a CRC over two parts equals the CRC of the whole.
  EXPECT_EQ(crc32("6789", crc32("12345")), 0xCBF43926u);
}

std::string smallFile(std::size_t chunk_size, int messages = 50,
                      Compression compression = Compression::kNone) {
  McapWriterParams p;
  p.chunk_size_bytes = chunk_size;
  p.compression = compression;
  McapWriter w(p);
  const auto s = w.addSchema("pkg/msg/A", "ros2msg", "int32 a\n");
  const auto c0 = w.addChannel(s, "/a", "cdr", {{"k", "v"}});
  const auto c1 = w.addChannel(s, "/b", "cdr");
  for (int i = 0; i < messages; ++i)
    w.addMessage(i % 3 ? c0 : c1, 1000 + i, 1000 + i, std::string(i % 7, char('a' + i % 26)));
  return w.finish();
}

TEST(Mcap, StartsAndEndsWithTheMagicAndRoundTrips) {
  for (std::size_t chunk : {std::size_t{0}, std::size_t{64}, std::size_t{1} << 20}) {
    const std::string bytes = smallFile(chunk);
    EXPECT_EQ(bytes.substr(0, 8), std::string("\x89MCAP0\r\n", 8));
    EXPECT_EQ(bytes.substr(bytes.size() - 8), std::string("\x89MCAP0\r\n", 8));
    const McapFile f = readMcap(bytes, "t.mcap");
    EXPECT_EQ(f.profile, "ros2");
    ASSERT_EQ(f.messages.size(), 50u);
    EXPECT_TRUE(f.has_summary);
    EXPECT_TRUE(f.data_crc_checked);
    // 64-byte chunks close after 2 or 3 message records of 31..37 bytes: 17 to 25 chunks.
    if (chunk == 64) {
      EXPECT_GE(f.chunk_count, 17u);
      EXPECT_LE(f.chunk_count, 25u);
    } else {
      EXPECT_EQ(f.chunk_count, chunk == 0 ? 0u : 1u);
    }
    for (int i = 0; i < 50; ++i) {
      const McapMessage& m = f.messages[i];
      EXPECT_EQ(m.log_time_ns, 1000u + i);
      EXPECT_EQ(m.data, std::string(i % 7, char('a' + i % 26)));
      EXPECT_EQ(m.channel_id, i % 3 ? 0 : 1);
    }
    // Sequence numbers count each channel's messages from 0.
    EXPECT_EQ(f.messages[3].sequence, 1u);  // the second message on /b (i = 0, 3)
    EXPECT_EQ(f.channels.at(0).metadata.at(0).second, "v");
  }
}

TEST(Mcap, EveryFlippedByteOfAChunkedFileIsCaughtOrHarmless) {
  // Flipping any byte either throws InputError or still reads 50 messages (a byte inside an
  // index record the linear reader skips, or a CRC field itself...). It never crashes.
  const std::string good = smallFile(64);
  int caught = 0;
  for (std::size_t i = 0; i < good.size(); ++i) {
    std::string bad = good;
    bad[i] = static_cast<char>(bad[i] ^ 0x5A);
    try {
      readMcap(bad, "t.mcap");
    } catch (const InputError& e) {
      ++caught;
      EXPECT_EQ(std::string(e.what()).rfind("t.mcap", 0), 0u) << e.what();
    }
  }
  // The data section and the summary are covered by CRCs: all but a handful must be caught.
  EXPECT_GT(caught, int(good.size() * 9 / 10));
}

TEST(Mcap, EveryTruncationIsAnInputError) {
  const std::string good = smallFile(128);
  for (std::size_t n = 0; n < good.size(); ++n)
    EXPECT_THROW(readMcap(good.substr(0, n), "t.mcap"), InputError) << n;
}

template <typename T>
void putLe(std::string& out, T v) {
  out.append(reinterpret_cast<const char*>(&v), sizeof(T));
}
void putRecord(std::string& out, std::uint8_t op, const std::string& body) {
  out.push_back(static_cast<char>(op));
  putLe<std::uint64_t>(out, body.size());
  out += body;
}
void putString(std::string& out, const std::string& s) {
  putLe<std::uint32_t>(out, static_cast<std::uint32_t>(s.size()));
  out += s;
}

TEST(Mcap, RefusesUnknownCompressionsNamingTheCompression) {
  // Written by hand from the spec: magic, Header, one "brotli" Chunk, DataEnd, Footer, magic.
  std::string f("\x89MCAP0\r\n", 8), header, chunk, data_end, footer;
  putString(header, "ros2");
  putString(header, "hand");
  putRecord(f, 0x01, header);
  for (int i = 0; i < 3; ++i) putLe<std::uint64_t>(chunk, 0);  // start, end, uncompressed_size
  putLe<std::uint32_t>(chunk, 0);
  putString(chunk, "brotli");
  putLe<std::uint64_t>(chunk, 4);
  chunk += "abcd";
  putRecord(f, 0x06, chunk);
  putLe<std::uint32_t>(data_end, 0);
  putRecord(f, 0x0F, data_end);
  for (int i = 0; i < 2; ++i) putLe<std::uint64_t>(footer, 0);
  putLe<std::uint32_t>(footer, 0);
  putRecord(f, 0x02, footer);
  f += std::string("\x89MCAP0\r\n", 8);
  try {
    readMcap(f, "z.mcap");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("compression \"brotli\""), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("z.mcap: offset"), std::string::npos) << e.what();
  }
}

// Rewrites the single chunk of a file compressed by an independent tool (the zstd or lz4 command
// line programs): records before the chunk kept, chunk re-packed, no indexes or summary.
std::string recompressed(const std::string& file, const std::string& tool,
                         const std::string& compression) {
  std::size_t pos = 8, chunk_at = 0;
  while (pos < file.size() - 8) {
    std::uint64_t len;
    std::memcpy(&len, file.data() + pos + 1, 8);
    if (file[pos] == 0x06) chunk_at = pos;
    if (file[pos] == 0x06 || file[pos] == 0x0F) break;
    pos += 9 + len;
  }
  EXPECT_GT(chunk_at, 0u);
  // Chunk body: start, end, uncompressed_size (u64 x3), crc (u32), compression "" (u32 0),
  // records length (u64), records.
  const std::size_t body = chunk_at + 9;
  std::uint64_t records_len;
  std::memcpy(&records_len, file.data() + body + 32, 8);
  const std::string records = file.substr(body + 40, records_len);
  const test::ScratchDir scratch("mcap_chunk");
  const auto in = scratch / "chunk", out = scratch / ("chunk." + compression);
  writeFileAtomic(in, records);
  if (std::system((tool + " -q -c '" + in.string() + "' > '" + out.string() + "'").c_str()) != 0)
    return {};
  const std::string packed = readFile(out);
  std::string f = file.substr(0, chunk_at), chunk, data_end, footer;
  chunk = file.substr(body, 28);  // start, end, uncompressed_size, uncompressed_crc
  putString(chunk, compression);
  putLe<std::uint64_t>(chunk, packed.size());
  chunk += packed;
  putRecord(f, 0x06, chunk);
  putLe<std::uint32_t>(data_end, 0);
  putRecord(f, 0x0F, data_end);
  for (int i = 0; i < 2; ++i) putLe<std::uint64_t>(footer, 0);
  putLe<std::uint32_t>(footer, 0);
  putRecord(f, 0x02, footer);
  return f + std::string("\x89MCAP0\r\n", 8);
}

TEST(Mcap, ReadsChunksCompressedByTheZstdAndLz4Tools) {
  const std::string plain = smallFile(1 << 20);
  const McapFile reference = readMcap(plain, "p.mcap");
  for (const auto& [tool, compression] :
       {std::pair<std::string, std::string>{"zstd", "zstd"}, {"lz4", "lz4"}}) {
    if (std::system(("command -v " + tool + " > /dev/null").c_str()) != 0) {
      std::cout << tool << " not installed: " << compression << " case not run\n";
      continue;
    }
    const std::string packed = recompressed(plain, tool, compression);
    ASSERT_FALSE(packed.empty()) << tool;
    const McapFile f = readMcap(packed, "c.mcap");
    ASSERT_EQ(f.messages.size(), reference.messages.size()) << compression;
    for (std::size_t i = 0; i < f.messages.size(); ++i)
      EXPECT_EQ(f.messages[i].data, reference.messages[i].data);
    // A corrupt frame (bytes flipped in the middle) is an InputError naming the chunk.
    std::string bad = packed;
    for (std::size_t i = bad.size() / 2; i < bad.size() / 2 + 8; ++i) bad[i] = char(bad[i] ^ 0x55);
    EXPECT_THROW(readMcap(bad, "c.mcap"), InputError) << compression;
  }
}

TEST(Mcap, ChunksCompressedWithTheLinkedZstdAndLz4RoundTrip) {
  const McapFile plain = readMcap(smallFile(256, 400), "p.mcap");
  for (const Compression c : {Compression::kZstd, Compression::kLz4}) {
    const std::string packed = smallFile(256, 400, c);
    const McapFile f = readMcap(packed, "c.mcap");
    EXPECT_EQ(f.chunk_count, plain.chunk_count);
    ASSERT_EQ(f.messages.size(), plain.messages.size());
    for (std::size_t i = 0; i < f.messages.size(); ++i)
      ASSERT_EQ(f.messages[i].data, plain.messages[i].data) << i;
    // The chunk records name their compression.
    const std::string name(mcapCompressionName(c));
    EXPECT_NE(packed.find(std::string("\0\0\0", 3) + name), std::string::npos) << name;
    // Truncations and corrupt bytes (sampled) are InputErrors or harmless, never a crash.
    for (std::size_t n = 0; n < packed.size(); n += 61)
      EXPECT_THROW(readMcap(packed.substr(0, n), "c.mcap"), InputError) << name << " " << n;
    for (std::size_t i = 0; i < packed.size(); i += 41) {
      std::string bad = packed;
      bad[i] = static_cast<char>(bad[i] ^ 0x5A);
      try {
        readMcap(bad, "c.mcap");
      } catch (const InputError&) {
      }
    }
  }
}

TEST(Mcap, RefusesMessagesOnUndefinedChannels) {
  McapWriterParams p;
  p.chunk_size_bytes = 0;
  McapWriter w(p);
  const auto s = w.addSchema("x", "ros2msg", "");
  w.addChannel(s, "/x", "cdr");
  w.addMessage(0, 1, 1, "m");
  std::string plain = w.finish();
  // Message record: opcode 5, length 23 (2 + 4 + 8 + 8 + 1); set its channel_id to 9. The data
  // section CRC would catch the edit first, so zero it ("not computed", allowed by the spec).
  const auto msg = plain.find(std::string("\x05\x17", 2) + std::string(7, '\0'));
  ASSERT_NE(msg, std::string::npos);
  plain[msg + 9] = 9;
  const auto data_end = plain.find(std::string("\x0f\x04", 2) + std::string(7, '\0'));
  ASSERT_NE(data_end, std::string::npos);
  std::memset(plain.data() + data_end + 9, 0, 4);
  try {
    readMcap(plain, "u.mcap");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("channel_id 9"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace slamprep::eval
