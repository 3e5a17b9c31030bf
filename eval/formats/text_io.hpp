#pragma once
// Fast, exact text I/O helpers for the dataset files: shortest round-trip number formatting
// (std::to_chars), strict field parsing (std::from_chars) with InputError messages that name the
// file, line and field, and whole-file read/write.

#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "slamprep/core/error.hpp"

namespace slamprep::eval {

/// Appends the shortest text that parses back to exactly `value`; "-0.0" for negative zero
/// (so JSON readers keep the sign), "nan"/"inf"/"-inf" never reach a file (callers check).
void appendDouble(std::string& out, double value);
void appendInt(std::string& out, std::int64_t value);

/// Where a field sits in a text file, for error messages: "file:line".
struct TextLocation {
  std::string file;      ///< file name as shown to the user
  std::size_t line = 0;  ///< 1-based; 0 when the line is not known

  std::string str() const;
};

/// Parses a whole field as a finite double (no leading '+', no "nan"/"inf"); throws InputError
/// naming `where` and `field` otherwise.
double parseFiniteDouble(std::string_view text, const TextLocation& where, std::string_view field);
/// Parses a whole field as a signed 64-bit integer; throws InputError otherwise.
std::int64_t parseInt64(std::string_view text, const TextLocation& where, std::string_view field);

/// Throws InputError unless `stamp_s` > `previous_s` (sorted, no duplicates).
void requireIncreasing(double previous_s, double stamp_s, const TextLocation& where,
                       std::string_view field);

/// Trims spaces, tabs and a trailing '\r'.
std::string_view trim(std::string_view text);
/// Splits on `separator` (fields are trimmed). Writes into `fields` to reuse its storage.
void splitFields(std::string_view line, char separator, std::vector<std::string_view>& fields);
/// Splits on runs of spaces/tabs (TUM style).
void splitWhitespace(std::string_view line, std::vector<std::string_view>& fields);

/// Iterates the lines of an in-memory text, 1-based line numbers, '\n' or "\r\n" endings.
class LineCursor {
 public:
  explicit LineCursor(std::string_view text) : text_(text) {}
  /// Next line without its ending; false at the end of the text.
  bool next(std::string_view& line);
  std::size_t lineNumber() const { return line_; }

 private:
  std::string_view text_;
  std::size_t pos_ = 0;
  std::size_t line_ = 0;
};

/// Calls row(values, where, fields) for every line of `text` that is neither blank nor a `#`
/// comment; each must hold exactly N whitespace-separated finite numbers, named by `columns` in
/// the errors (InputError naming file, line and column). The shape of TUM and relations files.
template <std::size_t N, typename RowFn>
void forEachNumberRow(std::string_view text, const std::string& file,
                      const std::array<const char*, N>& columns, RowFn&& row) {
  std::string layout;
  for (const char* c : columns) {
    if (!layout.empty()) layout += ' ';
    layout += c;
  }
  LineCursor cursor(text);
  std::string_view line;
  std::vector<std::string_view> fields;
  std::array<double, N> values{};
  while (cursor.next(line)) {
    line = trim(line);
    if (line.empty() || line.front() == '#') continue;
    const TextLocation where{file, cursor.lineNumber()};
    splitWhitespace(line, fields);
    if (fields.size() != N)
      throw InputError(where.str(), "expected " + std::to_string(N) + " columns \"" + layout +
                                        "\", got " + std::to_string(fields.size()));
    for (std::size_t c = 0; c < N; ++c) values[c] = parseFiniteDouble(fields[c], where, columns[c]);
    row(values, where, fields);
  }
}

/// The whole file; throws InputError("path", "cannot open ...") when it is missing or unreadable.
std::string readTextFile(const std::filesystem::path& path);
/// Creates/truncates `path`, writes `text` and fsyncs it; throws InputError on any failure.
void writeTextFile(const std::filesystem::path& path, std::string_view text);
/// The same for a text made piece by piece (a large file never whole in memory): `next_piece`
/// fills its (cleared) argument with the next piece and returns false when there is none.
void writeTextFile(const std::filesystem::path& path,
                   const std::function<bool(std::string&)>& next_piece);
/// A table written piece by piece: `header`, then append_row(out, k) for k = 0 .. rows - 1, 4096
/// rows a piece (a 2-hour log's IMU table is ~100 MB of text).
void writeRows(const std::filesystem::path& path, std::string_view header, std::size_t rows,
               const std::function<void(std::string&, std::size_t)>& append_row);

}  // namespace slamprep::eval
