// Replays the fuzz corpus (fuzz/corpus/<reader>/) and the minimised crashers kept as regressions
// (fuzz/regressions/<reader>/) through the same reader calls as the libFuzzer targets, in a
// normal (non-fuzzer) build: every input must be read or refused with InputError. Built with
// SLAMPREP_FUZZ_FORMATS_ONLY (the sanitizer subset, fuzz/CMakeLists.txt), it links only
// slamprep::formats and replays that library's readers.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

#include "slamprep/core/atomic_file.hpp"
#include "slamprep/core/error.hpp"
#ifdef SLAMPREP_FUZZ_FORMATS_ONLY
#include "slamprep/fuzz/format_readers.hpp"
#else
#include "slamprep/fuzz/readers.hpp"
#endif

namespace slamprep::fuzz {
namespace {
namespace fs = std::filesystem;

#ifdef SLAMPREP_FUZZ_FORMATS_ONLY
const std::vector<std::string>& replayedReaders() {
  return formatReaderNames();
}
void read(const std::string& reader, std::string_view bytes) {
  readFormatAs(reader, bytes);
}
#else
const std::vector<std::string>& replayedReaders() {
  return readerNames();
}
void read(const std::string& reader, std::string_view bytes) {
  readAs(reader, bytes);
}
#endif

std::vector<fs::path> inputs(const std::string& folder, const std::string& reader) {
  std::vector<fs::path> files;
  const fs::path dir = fs::path(SLAMPREP_SOURCE_DIR) / "fuzz" / folder / reader;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (e.is_regular_file()) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  return files;
}

/// Replays every input; returns how many were read without error.
std::size_t replay(const std::string& folder, const std::string& reader) {
  std::size_t accepted = 0;
  for (const fs::path& file : inputs(folder, reader)) {
    try {
      read(reader, readFile(file));
      ++accepted;
    } catch (const InputError&) {
    } catch (const std::exception& e) {
      ADD_FAILURE() << file << ": not an InputError: " << e.what();
    }
  }
  return accepted;
}

class FuzzReplay : public ::testing::TestWithParam<std::string> {};

TEST_P(FuzzReplay, CorpusIsReadOrRefusedWithInputError) {
  const std::string reader = GetParam();
  // The seed corpus holds at least one valid input per reader (docs/export.md, "Fuzzing").
  ASSERT_FALSE(inputs("corpus", reader).empty()) << "fuzz/corpus/" << reader << " is empty";
  EXPECT_GT(replay("corpus", reader), 0u) << "no corpus input of " << reader << " is valid";
}

// Every finding of the fuzzers, minimised, once fixed (docs/export.md, "Fuzzing"). The first
// ones (suite, censi, world, scenario) were yaml-cpp or nlohmann exceptions escaping the readers.
TEST_P(FuzzReplay, RegressionsAreRefusedWithInputError) {
  replay("regressions", GetParam());
}

INSTANTIATE_TEST_SUITE_P(Readers, FuzzReplay, ::testing::ValuesIn(replayedReaders()));

}  // namespace
}  // namespace slamprep::fuzz
