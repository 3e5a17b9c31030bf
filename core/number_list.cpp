#include "slamprep/core/number_list.hpp"

#include <charconv>
#include <cmath>

namespace slamprep {

std::optional<std::vector<double>> parseNumberList(std::string_view text,
                                                   const NumberListRule& rule, std::string* error) {
  std::vector<double> numbers;
  while (!text.empty()) {
    const std::size_t comma = text.find(',');
    const std::string_view item = text.substr(0, comma);
    double value = 0.0;
    const auto [end, ec] = std::from_chars(item.data(), item.data() + item.size(), value);
    if (ec != std::errc() || end != item.data() + item.size() || !std::isfinite(value) ||
        value < rule.min || value > rule.max) {
      if (error) *error = std::string("'").append(item).append("' is not ").append(rule.what);
      return std::nullopt;
    }
    numbers.push_back(value);
    if (numbers.size() > rule.max_count) {
      if (error) *error = "more than " + std::to_string(rule.max_count) + " numbers";
      return std::nullopt;
    }
    text = comma == std::string_view::npos ? std::string_view{} : text.substr(comma + 1);
  }
  return numbers;
}

}  // namespace slamprep
