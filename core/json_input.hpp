#pragma once
// JSON read from files the user hands over, checked before nlohmann parses it: nesting depth (a
// deeply nested value crashed every reader by recursion and grew on every rewrite) and keys
// repeated in one object (nlohmann keeps one of them silently). docs/design.md, "Input limits".

#include <cstddef>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

namespace slamprep {

/// Arrays and objects nested deeper than this are refused; slamprep's own files use at most 8.
inline constexpr int kMaxJsonDepth = 64;

/// Throws InputError("file:line", ...) for nesting deeper than kMaxJsonDepth or a key that
/// appears twice in one object. `text` may hold several values (one per line, or concatenated);
/// its first line is `first_line` of `file`. Syntax errors are left to the parser.
void checkJsonStructure(std::string_view text, const std::string& file, std::size_t first_line = 1);

/// checkJsonStructure, then the parse; a syntax error or a number out of range is
/// InputError("file:line", "bad JSON: ...").
nlohmann::json parseJsonInput(std::string_view text, const std::string& file,
                              std::size_t first_line = 1);

/// A JSON file whole, read by readInputFile (a regular file of at most kMaxRecordFileBytes)
/// and parsed by parseJsonInput; `what` names it in messages ("trial result").
nlohmann::json readJsonFile(const std::filesystem::path& file, std::string_view what);

}  // namespace slamprep
