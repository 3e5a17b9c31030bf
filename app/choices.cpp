#include "slamprep/app/choices.hpp"

#include <algorithm>
#include <cmath>

#include "slamprep/core/enum_names.hpp"
#include "slamprep/core/error.hpp"
#include "slamprep/eval/formats/text_io.hpp"

namespace slamprep::app {

std::size_t editDistance(const std::string& a, const std::string& b) {
  // d[i][j]: distance between the first i characters of a and the first j of b.
  std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
  for (std::size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (std::size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t substitution = a[i - 1] == b[j - 1] ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + substitution});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  }
  return d[a.size()][b.size()];
}

std::optional<std::string> closestName(const std::string& typed,
                                       const std::vector<std::string>& valid) {
  std::optional<std::string> best;
  std::size_t best_distance = 0;
  for (const std::string& name : valid) {
    const std::size_t distance = editDistance(typed, name);
    if (!best || distance < best_distance) {
      best = name;
      best_distance = distance;
    }
  }
  if (!best) return std::nullopt;
  const std::size_t longer = std::max(typed.size(), best->size());
  if (best_distance <= std::max<std::size_t>(2, longer / 3)) return best;
  // A part of one name reads as an abbreviation ("calib", "linear"); only when it is unique.
  std::optional<std::string> containing;
  for (const std::string& name : valid) {
    if (typed.size() < 3 || name.find(typed) == std::string::npos) continue;
    if (containing) return std::nullopt;
    containing = name;
  }
  return containing;
}

std::string joined(const std::vector<std::string>& names, const std::string& separator) {
  std::string out;
  for (const std::string& name : names) out += (out.empty() ? "" : separator) + name;
  return out;
}

std::string unknownChoice(const std::string& what, const std::string& typed,
                          const std::vector<std::string>& valid) {
  std::string message = unknownNameMessage(what, typed, valid);
  if (const auto closest = closestName(typed, valid))
    message += "; did you mean '" + *closest + "'?";
  return message;
}

CLI::Validator oneOf(const std::string& what, std::vector<std::string> valid) {
  const std::string description = "{" + joined(valid, ",") + "}";
  return CLI::Validator(
      [what, valid](std::string& value) {
        if (std::find(valid.begin(), valid.end(), value) != valid.end()) return std::string();
        return unknownChoice(what, value, valid);
      },
      description);
}

namespace {

// A finite number passing `ok`, else "must be <rule> (got <text>)".
CLI::Validator numberCheck(const char* rule, bool (*ok)(double)) {
  return CLI::Validator(
      [rule, ok](std::string& value) {
        double x = 0.0;
        if (CLI::detail::lexical_cast(value, x) && std::isfinite(x) && ok(x)) return std::string();
        return "must be " + std::string(rule) + " (got " + value + ")";
      },
      rule == std::string("> 0") ? "POSITIVE" : "NONNEGATIVE");
}

}  // namespace

CLI::Validator positive() {
  return numberCheck("> 0", [](double x) { return x > 0.0; });
}

CLI::Validator nonNegative() {
  return numberCheck(">= 0", [](double x) { return x >= 0.0; });
}

std::vector<double> parseList(const std::string& text, const char* flag,
                              const std::vector<const char*>& names) {
  std::vector<std::string_view> fields;
  slamprep::eval::splitFields(text, ',', fields);
  std::string expected;
  for (const char* n : names) expected += (expected.empty() ? "" : ",") + std::string(n);
  if (fields.size() != names.size()) throw InputError(flag, "expected " + expected);
  std::vector<double> values;
  for (std::size_t i = 0; i < names.size(); ++i)
    values.push_back(slamprep::eval::parseFiniteDouble(fields[i], {flag, 0}, names[i]));
  return values;
}

}  // namespace slamprep::app
