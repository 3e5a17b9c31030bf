#pragma once
// What the trial records' to_json/from_json share (trial_record.hpp): a field named by its enum
// (the one spelling of its JSON key), optional fields written only when set and read back only
// when present, and a number written as null (nlohmann writes NaN and infinity so) read back as
// NaN, so that a record read from a file writes the same bytes.

#include <cmath>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <type_traits>

#include "slamprep/core/enum_names.hpp"

namespace slamprep::eval {

/// The JSON key of a record field: its name in the field enum's table.
template <typename E, std::size_t N>
std::string keyOf(const EnumNames<E, N>& table, E field) {
  return std::string(nameOf(table, field));
}

/// `json[key]` as a T; a null read as NaN where T is floating point.
template <typename T>
T readField(const nlohmann::json& in, const std::string& key) {
  const nlohmann::json& value = in.at(key);
  if constexpr (std::is_floating_point_v<T>)
    if (value.is_null()) return std::nan("");
  return value.get<T>();
}

/// Writes `key` only when `value` is set.
template <typename T>
void writeOptional(nlohmann::json& out, const std::string& key, const std::optional<T>& value) {
  if (value) out[key] = *value;
}

/// Reads `key` when present, else nullopt.
template <typename T>
std::optional<T> readOptional(const nlohmann::json& in, const std::string& key) {
  if (!in.contains(key)) return std::nullopt;
  return readField<T>(in, key);
}

}  // namespace slamprep::eval
