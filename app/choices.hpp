#pragma once
// Named choices on the command line (--method, --format, commands): an unknown name is answered
// with the valid ones and the closest of them, so a typo costs one more try, not a docs search.

#include <CLI/CLI.hpp>
#include <optional>
#include <string>
#include <vector>

namespace slamprep::app {

/// Edit distance with adjacent transpositions (optimal string alignment): "cerse" -> "ceres" is 1.
std::size_t editDistance(const std::string& a, const std::string& b);

/// The valid name a typo most likely meant: the nearest by editDistance() when it is within a
/// third of the longer name (at least 2), else the one valid name that contains the typed text
/// ("calib" -> "calibrate", "linear" -> "odom-linear").
std::optional<std::string> closestName(const std::string& typed,
                                       const std::vector<std::string>& valid);

/// "unknown method 'cerse' (valid: direct, model, ...); did you mean 'ceres'?"
std::string unknownChoice(const std::string& what, const std::string& typed,
                          const std::vector<std::string>& valid);

/// A CLI11 check that accepts exactly `valid` and otherwise fails with unknownChoice().
CLI::Validator oneOf(const std::string& what, std::vector<std::string> valid);

/// Checks for numeric options: a finite number > 0 / >= 0, else "must be > 0 (got 0)"
/// (CLI11's PositiveNumber answers "Value 0 not in range 0.000000 to 1.797e308").
CLI::Validator positive();
CLI::Validator nonNegative();

/// "a|b|c", for option help.
std::string joined(const std::vector<std::string>& names, const std::string& separator = "|");

/// Comma-separated finite numbers, as many as `names` ("r_L,r_R,b" for --nominal); InputError
/// naming `flag` and the field otherwise.
std::vector<double> parseList(const std::string& text, const char* flag,
                              const std::vector<const char*>& names);

}  // namespace slamprep::app
