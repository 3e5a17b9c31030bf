#include "slamprep/core/json_input.hpp"

#include <algorithm>
#include <array>
#include <deque>
#include <unordered_map>
#include <vector>

#include "slamprep/core/error.hpp"
#include "slamprep/core/input_file.hpp"

namespace slamprep {
namespace {

/// One open array or object: the keys seen so far (objects) and the line each was first seen on.
struct Level {
  bool object = false;
  bool expect_key = false;
  std::unordered_map<std::string_view, std::size_t> keys;
};

/// Walks the text once: strings are skipped whole (escapes included), brackets counted.
class StructureScan {
 public:
  StructureScan(std::string_view text, const std::string& file, std::size_t first_line)
      : text_(text), file_(file), line_(first_line) {}

  void run() {
    for (pos_ = 0; pos_ < text_.size(); ++pos_) {
      skipPlain();
      if (pos_ == text_.size()) return;
      const char c = text_[pos_];
      if (c == '\n') ++line_;
      if (c == '"')
        string();
      else if (c == '{' || c == '[')
        open(c == '{');
      else if ((c == '}' || c == ']') && !levels_.empty())
        levels_.pop_back();
      else if (c == ',' && !levels_.empty() && levels_.back().object)
        levels_.back().expect_key = true;
    }
  }

 private:
  std::string where() const { return file_ + ":" + std::to_string(line_); }

  // Moves past the characters that change nothing here (digits, letters, blanks; commas inside
  // arrays): a scan line's numbers are most of a dataset, so this loop is what reading costs.
  void skipPlain() {
    static constexpr auto kMarks = [] {
      std::array<bool, 256> marks{};
      for (unsigned char c : std::string_view("\"{}[]\n,")) marks[c] = true;
      return marks;
    }();
    const bool in_object = !levels_.empty() && levels_.back().object;
    while (pos_ < text_.size()) {
      const unsigned char c = static_cast<unsigned char>(text_[pos_]);
      if (kMarks[c] && (c != ',' || in_object)) return;
      ++pos_;
    }
  }

  void open(bool object) {
    if (static_cast<int>(levels_.size()) >= kMaxJsonDepth)
      throw InputError(where(), "JSON nested deeper than " + std::to_string(kMaxJsonDepth) +
                                    " levels (arrays and objects)");
    levels_.push_back({object, object, {}});
  }

  // A string from its opening quote; a key when an object expects one.
  void string() {
    const std::size_t begin = pos_ + 1;
    bool escaped = false;
    std::size_t end = begin;
    for (; end < text_.size(); ++end) {
      if (text_[end] == '\n') ++line_;  // not valid JSON; the parser reports it
      if (text_[end] == '"' && !escaped) break;
      escaped = !escaped && text_[end] == '\\';
    }
    pos_ = std::min(end, text_.size());
    if (levels_.empty() || !levels_.back().expect_key) return;
    levels_.back().expect_key = false;
    key(text_.substr(begin, end - begin), end < text_.size());
  }

  void key(std::string_view raw, bool closed) {
    std::string_view name = raw;
    if (closed && raw.find('\\') != std::string_view::npos) {
      // Appended piecewise: GCC 12 warns falsely (-Wrestrict) on "\"" + std::string.
      std::string quoted(1, '"');
      quoted.append(raw).push_back('"');
      try {  // "\u0061" and "a" are the same key
        decoded_.push_back(nlohmann::json::parse(quoted).get<std::string>());
        name = decoded_.back();
      } catch (const nlohmann::json::exception&) {
        return;  // a bad escape: the parser names it
      }
    }
    const auto [it, inserted] = levels_.back().keys.emplace(name, line_);
    if (!inserted)
      throw InputError(where(), "key \"" + std::string(name) +
                                    "\" appears twice in one object (first on line " +
                                    std::to_string(it->second) + ")");
  }

  std::string_view text_;
  const std::string& file_;
  std::size_t line_;
  std::size_t pos_ = 0;
  std::vector<Level> levels_;
  std::deque<std::string> decoded_;  ///< keys with escapes, decoded (stable addresses)
};

std::size_t lineOfByte(std::string_view text, std::size_t byte, std::size_t first_line) {
  const std::size_t end = std::min(byte, text.size());
  return first_line + static_cast<std::size_t>(std::count(text.begin(), text.begin() + end, '\n'));
}

}  // namespace

void checkJsonStructure(std::string_view text, const std::string& file, std::size_t first_line) {
  StructureScan(text, file, first_line).run();
}

nlohmann::json parseJsonInput(std::string_view text, const std::string& file,
                              std::size_t first_line) {
  checkJsonStructure(text, file, first_line);
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    throw InputError(file + ":" + std::to_string(lineOfByte(text, e.byte, first_line)),
                     std::string("bad JSON: ") + e.what());
  } catch (const nlohmann::json::exception& e) {  // out_of_range: a number like 1e999
    throw InputError(file, std::string("bad JSON: ") + e.what());
  }
}

nlohmann::json readJsonFile(const std::filesystem::path& file, std::string_view what) {
  return parseJsonInput(readInputFile(file, what, kMaxRecordFileBytes), file.string());
}

}  // namespace slamprep
