// Input limits (docs/design.md "Input limits"): JSON nested deep enough to crash every reader by
// recursion (depth 200 000) or to grow 22 KB into a 200 MB rewrite (depth 10 000), keys repeated
// in one object, and input files that never end (/dev/zero) or are larger than any real one.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <fstream>
#include <string>

#include "slamprep/core/atomic_file.hpp"
#include "slamprep/core/error.hpp"
#include "slamprep/core/input_file.hpp"
#include "slamprep/core/json_input.hpp"
#include "slamprep/tests/support/error_of.hpp"
#include "slamprep/tests/support/scratch_dir.hpp"

namespace slamprep {
namespace {

std::string nested(int depth) {
  return std::string(depth, '[') + "1" + std::string(depth, ']');
}

using test::errorOf;

TEST(JsonInput, NestingUpToTheLimitIsRead) {
  EXPECT_EQ(parseJsonInput(nested(kMaxJsonDepth), "d.json").dump(), nested(kMaxJsonDepth));
}

TEST(JsonInput, DeeperNestingIsRefusedNamingFileAndLine) {
  EXPECT_EQ(errorOf([] { parseJsonInput("{\n\"a\": " + nested(kMaxJsonDepth) + "}", "d.json"); }),
            "d.json:2: JSON nested deeper than 64 levels (arrays and objects)");
  // The depths of the issue: refused without recursion (no crash, no 200 MB rewrite).
  for (int depth : {10000, 200000})
    EXPECT_NE(errorOf([&] { parseJsonInput(nested(depth), "d.json"); }).find("deeper than 64"),
              std::string::npos)
        << depth;
}

TEST(JsonInput, BracketsInsideStringsAreNotNesting) {
  const std::string text = "{\"a\": \"" + std::string(100, '[') + "\\\"{\"}";
  EXPECT_EQ(parseJsonInput(text, "d.json")["a"], std::string(100, '[') + "\"{");
}

TEST(JsonInput, RepeatedKeyIsRefusedWithBothLines) {
  EXPECT_EQ(errorOf([] {
              parseJsonInput("{\"walls\": 1,\n\"b\": {\"walls\": 2},\n\"walls\": 3}", "w.json");
            }),
            "w.json:3: key \"walls\" appears twice in one object (first on line 1)");
  // The same key spelled with an escape is the same key.
  EXPECT_NE(errorOf([] { parseJsonInput(R"({"a": 1, "\u0061": 2})", "w.json"); }), "");
}

TEST(JsonInput, SameKeyInDifferentObjectsIsFine) {
  const auto j = parseJsonInput(R"([{"a": 1}, {"a": 2}, {"b": {"a": 3}, "a": 4}])", "ok.json");
  EXPECT_EQ(j[2]["a"], 4);
}

TEST(JsonInput, LinesOfAFileCountFromTheirFirstLine) {
  EXPECT_EQ(errorOf([] { checkJsonStructure(R"({"T": 1, "T": 2})", "t.jsonl", 7); }),
            "t.jsonl:7: key \"T\" appears twice in one object (first on line 7)");
  EXPECT_EQ(errorOf([] { parseJsonInput("{\"a\":\n ]", "bad.json", 3); }).rfind("bad.json:4:", 0),
            0u);
}

class InputFileTest : public ::testing::Test {
 protected:
  test::ScratchDir scratch_{"input_file"};
};

TEST_F(InputFileTest, DevicesFifosAndFoldersAreRefusedUpFront) {
  EXPECT_EQ(errorOf([] { readInputFile("/dev/zero", "world file", kMaxYamlFileBytes); }),
            "/dev/zero: cannot read world file: a character device, not a regular file");
  const auto fifo = scratch_ / "fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_NE(errorOf([&] {
              readInputFile(fifo, "suite file", kMaxYamlFileBytes);
            }).find("a FIFO (pipe), not a regular file"),
            std::string::npos);
  EXPECT_NE(errorOf([&] {
              readInputFile(scratch_.path(), "world file", kMaxYamlFileBytes);
            }).find("a directory"),
            std::string::npos);
  EXPECT_EQ(errorOf([&] { readInputFile(scratch_ / "none", "world file", 10); }),
            (scratch_ / "none").string() + ": cannot open world file");
  EXPECT_EQ(errorOf([] { readFile("/dev/zero"); }), "/dev/zero: not a regular file");
}

TEST_F(InputFileTest, SizeLimitIsInclusive) {
  const auto file = scratch_ / "f.yaml";
  std::ofstream(file) << std::string(2048, 'x');
  EXPECT_EQ(readInputFile(file, "world file", 2048).size(), 2048u);
  EXPECT_EQ(errorOf([&] { readInputFile(file, "world file", 2047); }),
            file.string() + ": world file of 2048 bytes is larger than the limit of 2047 bytes");
}

}  // namespace
}  // namespace slamprep
