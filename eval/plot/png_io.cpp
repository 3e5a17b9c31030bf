// Image pixel access, and PNG files through libpng. libpng reports errors by longjmp, so the setjmp
// frames below hold only plain C data; everything with a destructor lives in the callers.

#include <png.h>
#include <unistd.h>

#include <atomic>
#include <cassert>
#include <cerrno>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <string>
#include <system_error>
#include <vector>

#include "slamprep/core/error.hpp"
#include "slamprep/eval/plot/plot.hpp"

namespace slamprep::eval::plot {
namespace {

/// Writes 8-bit RGB rows to an open file; returns false (with libpng's message) on failure.
bool writeRows(std::FILE* file, int width, int height, png_bytep* rows, char* error,
               std::size_t error_size) {
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  if (!png) return false;
  png_infop info = png_create_info_struct(png);
  if (!info || setjmp(png_jmpbuf(png))) {
    std::snprintf(error, error_size, "libpng failed while encoding");
    png_destroy_write_struct(&png, info ? &info : nullptr);
    return false;
  }
  png_init_io(png, file);
  png_set_IHDR(png, info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height), 8,
               PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  png_text text{};
  char key[] = "Software";
  char value[] = "slamprep";
  text.compression = PNG_TEXT_COMPRESSION_NONE;
  text.key = key;
  text.text = value;
  png_set_text(png, info, &text, 1);  // no tIME chunk: same figure, same bytes
  png_write_info(png, info);
  png_write_image(png, rows);
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return true;
}

/// A temporary name beside `path`, unique within this process and across processes.
std::filesystem::path temporaryPath(const std::filesystem::path& path) {
  static std::atomic<unsigned> counter{0};
  return path.string() + ".tmp" + std::to_string(::getpid()) + "_" + std::to_string(counter++);
}

}  // namespace

std::array<std::uint8_t, 4> Image::pixel(int x, int y) const {
  assert(x >= 0 && y >= 0 && x < width && y < height);
  const std::size_t i = (static_cast<std::size_t>(y) * width + x) * 4;
  return {rgba[i], rgba[i + 1], rgba[i + 2], rgba[i + 3]};
}

void writePng(const Image& image, const std::filesystem::path& path) {
  if (image.width <= 0 || image.height <= 0 ||
      image.rgba.size() != static_cast<std::size_t>(image.width) * image.height * 4) {
    throw InputError(path.string(), "cannot write an empty or malformed image");
  }
  std::vector<png_byte> rgb(static_cast<std::size_t>(image.width) * image.height * 3);
  for (std::size_t i = 0, n = rgb.size() / 3; i < n; ++i) {
    std::memcpy(&rgb[i * 3], &image.rgba[i * 4], 3);
  }
  std::vector<png_bytep> rows(static_cast<std::size_t>(image.height));
  for (int y = 0; y < image.height; ++y) {
    rows[static_cast<std::size_t>(y)] = &rgb[static_cast<std::size_t>(y) * image.width * 3];
  }

  const std::filesystem::path temporary = temporaryPath(path);
  std::FILE* file = std::fopen(temporary.c_str(), "wb");
  if (!file) throw InputError(path.string(), std::string("cannot write: ") + std::strerror(errno));
  char error[256] = "out of memory";
  const bool encoded =
      writeRows(file, image.width, image.height, rows.data(), error, sizeof(error));
  const bool closed = std::fclose(file) == 0;
  std::error_code ec;
  if (!encoded || !closed) {
    std::filesystem::remove(temporary, ec);
    throw InputError(path.string(), encoded ? "cannot write: disk full?" : error);
  }
  std::filesystem::rename(temporary, path, ec);
  if (ec) {
    std::filesystem::remove(temporary, ec);
    throw InputError(path.string(), "cannot move the finished file into place: " + ec.message());
  }
}

Image readPng(const std::filesystem::path& path) {
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&png, path.c_str())) {
    const std::string message = png.message;
    png_image_free(&png);
    throw InputError(path.string(), "cannot read PNG: " + message);
  }
  png.format = PNG_FORMAT_RGBA;
  Image image{static_cast<int>(png.width), static_cast<int>(png.height),
              std::vector<std::uint8_t>(PNG_IMAGE_SIZE(png))};
  if (!png_image_finish_read(&png, nullptr, image.rgba.data(), 0, nullptr)) {
    const std::string message = png.message;
    png_image_free(&png);
    throw InputError(path.string(), "cannot decode PNG: " + message);
  }
  return image;
}

}  // namespace slamprep::eval::plot
