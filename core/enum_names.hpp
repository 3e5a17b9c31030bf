#pragma once
// Names of enum values as users type and read them (CLI flags, JSON, YAML): one table per enum,
// one lookup each way, and one wording for an unknown name, so every table answers alike.
//
//   constexpr auto kModeNames = std::to_array<EnumName<Mode>>({{Mode::kA, "a"}, {Mode::kB, "b"}});
//   nameOf(kModeNames, Mode::kB)                      -> "b"
//   findName(kModeNames, "c")                         -> nullopt
//   parseName(kModeNames, "c", "mode", "--mode")      -> InputError "--mode: unknown mode 'c' ..."

#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "slamprep/core/error.hpp"

namespace slamprep {

/// One row of a name table: a value and its name.
template <typename E>
using EnumName = std::pair<E, std::string_view>;

/// A name table; its order is the order names are listed in messages and --help.
template <typename E, std::size_t N>
using EnumNames = std::array<EnumName<E>, N>;

/// The name of `value`; "unknown" for a value the table lacks (a cast integer).
template <typename E, std::size_t N>
constexpr std::string_view nameOf(const EnumNames<E, N>& table, E value) {
  for (const auto& [v, name] : table)
    if (v == value) return name;
  return "unknown";
}

/// The value named `text` (exact, case-sensitive); nullopt for an unknown name.
template <typename E, std::size_t N>
constexpr std::optional<E> findName(const EnumNames<E, N>& table, std::string_view text) {
  for (const auto& [v, name] : table)
    if (name == text) return v;
  return std::nullopt;
}

/// Every name in table order, for --help, CLI checks and messages.
template <typename E, std::size_t N>
std::vector<std::string> namesOf(const EnumNames<E, N>& table) {
  std::vector<std::string> names;
  for (const auto& row : table) names.emplace_back(row.second);
  return names;
}

/// The names in table order joined with `separator` ("a, b", "a|b").
template <typename E, std::size_t N>
std::string joinedNames(const EnumNames<E, N>& table, std::string_view separator) {
  std::string out;
  for (std::size_t i = 0; i < N; ++i) out.append(i ? separator : "").append(table[i].second);
  return out;
}

/// "unknown mode 'c' (valid: a, b)": the one wording for a name not in a list.
std::string unknownNameMessage(std::string_view what, std::string_view text,
                               const std::vector<std::string>& valid);

/// The value named `text`; otherwise throws InputError(where, unknownNameMessage(what, ...)).
template <typename E, std::size_t N>
E parseName(const EnumNames<E, N>& table, std::string_view text, std::string_view what,
            const std::string& where) {
  if (const auto value = findName(table, text)) return *value;
  throw InputError(where, unknownNameMessage(what, text, namesOf(table)));
}

}  // namespace slamprep
