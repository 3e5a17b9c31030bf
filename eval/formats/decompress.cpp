#include "eval/formats/decompress.hpp"

#include <dlfcn.h>

#include "core/error.hpp"

namespace slamprep::eval {
namespace {

// The few C entry points used, declared as the libraries' headers declare them.
using ZstdDecompress = std::size_t (*)(void*, std::size_t, const void*, std::size_t);
using ZstdIsError = unsigned (*)(std::size_t);
using ZstdGetErrorName = const char* (*)(std::size_t);
using Lz4fCreate = std::size_t (*)(void**, unsigned);
using Lz4fFree = std::size_t (*)(void*);
using Lz4fDecompress = std::size_t (*)(void*, void*, std::size_t*, const void*, std::size_t*,
                                       const void*);
using Lz4fIsError = unsigned (*)(std::size_t);
constexpr unsigned kLz4fVersion = 100;  // LZ4F_VERSION

void* symbol(void* lib, const char* name) {
  return lib ? ::dlsym(lib, name) : nullptr;
}

struct Zstd {
  ZstdDecompress decompress = nullptr;
  ZstdIsError is_error = nullptr;
  ZstdGetErrorName error_name = nullptr;
};

const Zstd& zstd() {
  static const Zstd z = [] {
    void* lib = ::dlopen("libzstd.so.1", RTLD_NOW | RTLD_LOCAL);
    Zstd r;
    r.decompress = reinterpret_cast<ZstdDecompress>(symbol(lib, "ZSTD_decompress"));
    r.is_error = reinterpret_cast<ZstdIsError>(symbol(lib, "ZSTD_isError"));
    r.error_name = reinterpret_cast<ZstdGetErrorName>(symbol(lib, "ZSTD_getErrorName"));
    return r;
  }();
  return z;
}

struct Lz4 {
  Lz4fCreate create = nullptr;
  Lz4fFree free = nullptr;
  Lz4fDecompress decompress = nullptr;
  Lz4fIsError is_error = nullptr;
};

const Lz4& lz4() {
  static const Lz4 l = [] {
    void* lib = ::dlopen("liblz4.so.1", RTLD_NOW | RTLD_LOCAL);
    Lz4 r;
    r.create = reinterpret_cast<Lz4fCreate>(symbol(lib, "LZ4F_createDecompressionContext"));
    r.free = reinterpret_cast<Lz4fFree>(symbol(lib, "LZ4F_freeDecompressionContext"));
    r.decompress = reinterpret_cast<Lz4fDecompress>(symbol(lib, "LZ4F_decompress"));
    r.is_error = reinterpret_cast<Lz4fIsError>(symbol(lib, "LZ4F_isError"));
    return r;
  }();
  return l;
}

std::string unzstd(std::string_view data, std::uint64_t size, const std::string& where) {
  const Zstd& z = zstd();
  if (!z.decompress || !z.is_error)
    throw InputError(where, "zstd chunk: libzstd.so.1 not found (install libzstd1)");
  std::string out(size, '\0');
  const std::size_t n = z.decompress(out.data(), out.size(), data.data(), data.size());
  if (z.is_error(n))
    throw InputError(where, std::string("zstd chunk: corrupt (") +
                                (z.error_name ? z.error_name(n) : "error") + ")");
  if (n != size)
    throw InputError(where, "zstd chunk: " + std::to_string(n) + " bytes unpacked, " +
                                std::to_string(size) + " announced");
  return out;
}

std::string unlz4(std::string_view data, std::uint64_t size, const std::string& where) {
  const Lz4& l = lz4();
  if (!l.create || !l.free || !l.decompress || !l.is_error)
    throw InputError(where, "lz4 chunk: liblz4.so.1 not found (install liblz4-1)");
  void* ctx = nullptr;
  if (l.is_error(l.create(&ctx, kLz4fVersion)))
    throw InputError(where, "lz4 chunk: cannot create a decompression context");
  std::string out(size, '\0');
  std::size_t in_pos = 0, out_pos = 0, hint = 1;
  // Feed the frame until it ends (hint 0), the input runs out, or no progress is made.
  while (hint != 0 && in_pos < data.size()) {
    std::size_t out_n = out.size() - out_pos, in_n = data.size() - in_pos;
    hint = l.decompress(ctx, out.data() + out_pos, &out_n, data.data() + in_pos, &in_n, nullptr);
    if (l.is_error(hint)) {
      l.free(ctx);
      throw InputError(where, "lz4 chunk: corrupt frame");
    }
    if (out_n == 0 && in_n == 0) break;
    in_pos += in_n;
    out_pos += out_n;
  }
  l.free(ctx);
  if (hint != 0 || out_pos != size)
    throw InputError(where, "lz4 chunk: " + std::to_string(out_pos) + " bytes unpacked, " +
                                std::to_string(size) + " announced (truncated or corrupt frame)");
  return out;
}

}  // namespace

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

}  // namespace slamprep::eval
