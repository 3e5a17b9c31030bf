#include <gtest/gtest.h>

#include <fstream>
#include <iterator>

#include "slamprep/core/error.hpp"
#include "slamprep/eval/plot/plot.hpp"

namespace slamprep::eval::plot {
namespace {

std::filesystem::path scratchDir(const std::string& name) {
  const auto dir = std::filesystem::path(SLAMPREP_BINARY_DIR) / "test_scratch" / "plot" / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

std::string fileBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

Image gradient(int w, int h) {
  Image image{w, h, std::vector<std::uint8_t>(static_cast<std::size_t>(w) * h * 4)};
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      std::uint8_t* p = &image.rgba[(static_cast<std::size_t>(y) * w + x) * 4];
      p[0] = static_cast<std::uint8_t>(x), p[1] = static_cast<std::uint8_t>(y);
      p[2] = static_cast<std::uint8_t>(x ^ y), p[3] = 255;
    }
  }
  return image;
}

TEST(Png, RoundTripsPixels) {
  const auto path = scratchDir("roundtrip") / "g.png";
  const Image image = gradient(37, 23);
  writePng(image, path);
  const Image back = readPng(path);
  ASSERT_EQ(back.width, 37);
  ASSERT_EQ(back.height, 23);
  EXPECT_EQ(back.rgba, image.rgba);  // 8-bit RGB is lossless; alpha was 255
}

TEST(Png, SignatureTextChunkAndNoTimestamp) {
  const auto path = scratchDir("chunks") / "g.png";
  writePng(gradient(8, 8), path);
  const std::string bytes = fileBytes(path);
  ASSERT_GT(bytes.size(), 8u);
  EXPECT_EQ(bytes.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  EXPECT_NE(bytes.find(std::string("tEXtSoftware\0slamprep", 21)), std::string::npos);
  EXPECT_EQ(bytes.find("tIME"), std::string::npos);
}

TEST(Png, WritesAtomicallyAndLeavesNoTemporaries) {
  const auto dir = scratchDir("atomic");
  writePng(gradient(8, 8), dir / "a.png");
  writePng(gradient(9, 9), dir / "a.png");  // replaces the file
  EXPECT_EQ(readPng(dir / "a.png").width, 9);
  const auto count = std::distance(std::filesystem::directory_iterator(dir),
                                   std::filesystem::directory_iterator());
  EXPECT_EQ(count, 1);
}

TEST(Png, ErrorsNameThePath) {
  const auto dir = scratchDir("errors");
  try {
    writePng(gradient(4, 4), dir / "missing_dir" / "x.png");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("x.png"), std::string::npos) << e.what();
  }
  std::ofstream(dir / "not.png") << "hello";
  EXPECT_THROW(readPng(dir / "not.png"), InputError);
  EXPECT_THROW(readPng(dir / "absent.png"), InputError);
  EXPECT_THROW(writePng(Image{}, dir / "empty.png"), InputError);
}

}  // namespace
}  // namespace slamprep::eval::plot
