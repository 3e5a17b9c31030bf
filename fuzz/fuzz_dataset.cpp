// libFuzzer target for the dataset reader (fuzz/readers.hpp). InputError is the expected refusal;
// any other exception aborts, so libFuzzer records the input as a finding.
#include <cstdio>
#include <cstdlib>

#include "slamprep/core/error.hpp"
#include "slamprep/fuzz/readers.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    slamprep::fuzz::readAs("dataset", {reinterpret_cast<const char*>(data), size});
  } catch (const slamprep::InputError&) {
  } catch (const std::exception& e) {
    std::fprintf(stderr, "not an InputError: %s\n", e.what());
    std::abort();
  }
  return 0;
}
