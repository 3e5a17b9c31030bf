#pragma once
// A comma-separated list of numbers, as the simulator's list keys are written
// ("faults.dropped_beams.by_angle=1,0.5,0", "lidar.range_bias_by_beam_m=0.01,-0.02").

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace slamprep {

/// What a list may hold.
struct NumberListRule {
  double min = 0.0, max = 0.0;  ///< each number finite and within [min, max]
  std::size_t max_count = 0;
  const char* what = "";  ///< the rule in words, for the error: "a number >= 0"
};

/// The numbers of "a,b,c" ("" gives none) under `rule`; nullopt (and *error set, naming the
/// item) otherwise.
std::optional<std::vector<double>> parseNumberList(std::string_view text,
                                                   const NumberListRule& rule, std::string* error);

}  // namespace slamprep
