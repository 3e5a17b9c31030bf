#include "slamprep/eval/formats/compression.hpp"

#include <lz4frame.h>
#include <zstd.h>

#include <fstream>
#include <memory>
#include <stdexcept>

#include "slamprep/core/error.hpp"

namespace slamprep::eval {
namespace {

std::string unzstd(std::string_view data, std::uint64_t size, const std::string& where) {
  std::string out(size, '\0');
  const std::size_t n = ZSTD_decompress(out.data(), out.size(), data.data(), data.size());
  if (ZSTD_isError(n))
    throw InputError(where, std::string("zstd chunk: corrupt (") + ZSTD_getErrorName(n) + ")");
  if (n != size)
    throw InputError(where, "zstd chunk: " + std::to_string(n) + " bytes unpacked, " +
                                std::to_string(size) + " announced");
  return out;
}

using Lz4Context = std::unique_ptr<LZ4F_dctx, decltype(&LZ4F_freeDecompressionContext)>;

std::string unlz4(std::string_view data, std::uint64_t size, const std::string& where) {
  LZ4F_dctx* raw = nullptr;
  if (LZ4F_isError(LZ4F_createDecompressionContext(&raw, LZ4F_VERSION)))
    throw InputError(where, "lz4 chunk: cannot create a decompression context");
  const Lz4Context ctx(raw, &LZ4F_freeDecompressionContext);
  std::string out(size, '\0');
  std::size_t in_pos = 0, out_pos = 0, hint = 1;
  // Feed the frame until it ends (hint 0), the input runs out, or no progress is made.
  while (hint != 0 && in_pos < data.size()) {
    std::size_t out_n = out.size() - out_pos, in_n = data.size() - in_pos;
    hint = LZ4F_decompress(ctx.get(), out.data() + out_pos, &out_n, data.data() + in_pos, &in_n,
                           nullptr);
    if (LZ4F_isError(hint))
      throw InputError(where,
                       std::string("lz4 chunk: corrupt frame (") + LZ4F_getErrorName(hint) + ")");
    if (out_n == 0 && in_n == 0) break;
    in_pos += in_n;
    out_pos += out_n;
  }
  if (hint != 0 || out_pos != size)
    throw InputError(where, "lz4 chunk: " + std::to_string(out_pos) + " bytes unpacked, " +
                                std::to_string(size) + " announced (truncated or corrupt frame)");
  return out;
}

std::string zstd(std::string_view data) {
  std::string out(ZSTD_compressBound(data.size()), '\0');
  const std::size_t n =
      ZSTD_compress(out.data(), out.size(), data.data(), data.size(), ZSTD_CLEVEL_DEFAULT);
  if (ZSTD_isError(n)) throw std::runtime_error(std::string("zstd: ") + ZSTD_getErrorName(n));
  out.resize(n);
  return out;
}

std::string lz4(std::string_view data) {
  std::string out(LZ4F_compressFrameBound(data.size(), nullptr), '\0');
  const std::size_t n =
      LZ4F_compressFrame(out.data(), out.size(), data.data(), data.size(), nullptr);
  if (LZ4F_isError(n)) throw std::runtime_error(std::string("lz4: ") + LZ4F_getErrorName(n));
  out.resize(n);
  return out;
}

}  // namespace

Compression parseCompression(const std::string& name, const std::string& where) {
  return parseName(kCompressionNames, name, "compression", where);
}

std::string_view mcapCompressionName(Compression c) {
  return c == Compression::kNone ? "" : nameOf(kCompressionNames, c);  // MCAP: "" is none
}

bool plausibleUncompressedSize(std::uint64_t compressed_size, std::uint64_t uncompressed_size) {
  constexpr std::uint64_t kMax = std::uint64_t{1} << 30;
  return uncompressed_size <= kMax && uncompressed_size <= compressed_size * 4096 + (1 << 20);
}

std::string decompressChunk(std::string_view compression, std::string_view data,
                            std::uint64_t uncompressed_size, const std::string& where) {
  if (!plausibleUncompressedSize(data.size(), uncompressed_size))
    throw InputError(where, "uncompressed_size " + std::to_string(uncompressed_size) +
                                " is implausible for " + std::to_string(data.size()) +
                                " compressed bytes");
  if (compression == "zstd") return unzstd(data, uncompressed_size, where);
  if (compression == "lz4") return unlz4(data, uncompressed_size, where);
  throw InputError(where, "compression \"" + std::string(compression) +
                              "\" is not supported (only \"\", \"zstd\", \"lz4\")");
}

namespace {

using ZstdStream = std::unique_ptr<ZSTD_DCtx, decltype(&ZSTD_freeDCtx)>;

ZstdStream zstdStream(const std::string& where) {
  ZstdStream ctx(ZSTD_createDCtx(), &ZSTD_freeDCtx);
  if (!ctx) throw InputError(where, "zstd: cannot create a decompression context");
  return ctx;
}

/// Feeds `in` through `ctx`, handing each unpacked block to `sink`; returns ZSTD's last hint
/// (0: a frame ended exactly at the end of the input).
template <typename Sink>
std::size_t unzstdBlocks(ZSTD_DCtx* ctx, std::string_view in, std::string& block,
                         const std::string& where, Sink&& sink) {
  ZSTD_inBuffer input{in.data(), in.size(), 0};
  std::size_t hint = 1;
  while (input.pos < input.size) {
    ZSTD_outBuffer output{block.data(), block.size(), 0};
    hint = ZSTD_decompressStream(ctx, &output, &input);
    if (ZSTD_isError(hint))
      throw InputError(where, std::string("zstd: corrupt data (") + ZSTD_getErrorName(hint) + ")");
    sink(std::string_view(block.data(), output.pos));
  }
  // The input is consumed; flush what the decoder still holds.
  while (hint != 0) {
    ZSTD_outBuffer output{block.data(), block.size(), 0};
    hint = ZSTD_decompressStream(ctx, &output, &input);
    if (ZSTD_isError(hint))
      throw InputError(where, std::string("zstd: corrupt data (") + ZSTD_getErrorName(hint) + ")");
    if (output.pos == 0) break;  // needs more input: the frame is truncated
    sink(std::string_view(block.data(), output.pos));
  }
  return hint;
}

}  // namespace

std::string decompressZstd(std::string_view data, const std::string& where,
                           std::uint64_t max_size) {
  const ZstdStream ctx = zstdStream(where);
  std::string out, block(std::size_t{1} << 16, '\0');
  const std::size_t hint = unzstdBlocks(ctx.get(), data, block, where, [&](std::string_view b) {
    if (out.size() + b.size() > max_size)
      throw InputError(where, "zstd: unpacks to more than " + std::to_string(max_size) + " bytes");
    out.append(b);
  });
  if (hint != 0) throw InputError(where, "zstd: truncated frame");
  return out;
}

void decompressZstdFile(const std::filesystem::path& from, const std::filesystem::path& to) {
  const std::string where = from.string();
  std::ifstream in(from, std::ios::binary);
  if (!in) throw InputError(where, "cannot open");
  std::ofstream out(to, std::ios::binary | std::ios::trunc);
  if (!out) throw InputError(to.string(), "cannot create the decompressed copy");
  const ZstdStream ctx = zstdStream(where);
  std::string chunk(std::size_t{1} << 20, '\0'), block(ZSTD_DStreamOutSize(), '\0');
  std::size_t hint = 1;
  bool any = false;
  while (in) {
    in.read(chunk.data(), static_cast<std::streamsize>(chunk.size()));
    const auto n = static_cast<std::size_t>(in.gcount());
    if (n == 0) break;
    any = true;
    hint = unzstdBlocks(
        ctx.get(), std::string_view(chunk.data(), n), block, where,
        [&](std::string_view b) { out.write(b.data(), static_cast<std::streamsize>(b.size())); });
  }
  if (!any || hint != 0) throw InputError(where, "zstd: empty or truncated file");
  out.flush();
  if (!out) throw InputError(to.string(), "cannot write the decompressed copy (disk full?)");
}

std::string compressChunk(Compression c, std::string_view data) {
  if (c == Compression::kZstd) return zstd(data);
  if (c == Compression::kLz4) return lz4(data);
  return std::string(data);
}

}  // namespace slamprep::eval
