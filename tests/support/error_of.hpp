#pragma once
// The message of the InputError a call throws; empty when it throws none. For tests that check
// a refusal names its file, line and key.

#include <string>

#include "slamprep/core/error.hpp"

namespace slamprep::test {

template <typename Fn>
std::string errorOf(Fn&& fn) {
  try {
    fn();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace slamprep::test
