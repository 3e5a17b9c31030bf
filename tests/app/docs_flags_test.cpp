// The docs in step with the code: every `--flag` that README.md or docs/*.md gives a slamprep
// command must be in that command's --help. A flag belongs to a command when it follows
// `slamprep CMD` (or `CMD` at the start of a code span) in the same code span or code-block line
// (usage lines continued on the next indented line included), or when a code span starts with
// it inside a section whose heading or first usage line names the command.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using Flags = std::set<std::string>;

const std::vector<std::string> kCommands = {"bench",  "calibrate", "deskew", "export",
                                            "import", "match",     "merge",  "plot",
                                            "score",  "simulate",  "twin"};

bool isCommand(const std::string& word) {
  return std::find(kCommands.begin(), kCommands.end(), word) != kCommands.end();
}

/// The long options `slamprep CMD --help` lists.
Flags helpFlags(const std::string& command) {
  const std::string call = std::string(SLAMPREP_BINARY_DIR) + "/slamprep " + command + " --help";
  FILE* pipe = ::popen(call.c_str(), "r");
  EXPECT_NE(pipe, nullptr) << call;
  std::string text;
  std::array<char, 4096> buffer{};
  while (pipe && std::fgets(buffer.data(), buffer.size(), pipe)) text += buffer.data();
  if (pipe) {
    EXPECT_EQ(::pclose(pipe), 0) << call;
  }
  Flags flags;
  static const std::regex option(R"(^  (?:-\w,)?(--[a-z][a-z0-9-]*))");
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    for (std::smatch m; std::regex_search(line, m, option);) {
      flags.insert(m[1]);
      // "-q,--quiet" and "--jobs,-j": every long name on the line's option column.
      const std::string column = line.substr(0, line.find("  ", 2));
      static const std::regex any(R"(--[a-z][a-z0-9-]*)");
      for (auto it = std::sregex_iterator(column.begin(), column.end(), any);
           it != std::sregex_iterator(); ++it)
        flags.insert(it->str());
      break;
    }
  }
  return flags;
}

std::vector<std::string> words(const std::string& text) {
  std::istringstream in(text);
  std::vector<std::string> out;
  for (std::string w; in >> w;) out.push_back(w);
  return out;
}

/// `--set`, `--sbatch-arg=--time=1:00:00` -> `--sbatch-arg`; `[--left-joint/--right-joint]` ->
/// both. Only the part before '=' names flags.
std::vector<std::string> flagsIn(std::string word) {
  word = word.substr(0, word.find('='));
  static const std::regex flag(R"((?:^|[^\w-])(--[a-z][a-z0-9-]*))");
  std::vector<std::string> out;
  for (auto it = std::sregex_iterator(word.begin(), word.end(), flag); it != std::sregex_iterator();
       ++it)
    out.push_back((*it)[1]);
  return out;
}

/// `slamprep`, `./build/slamprep`, `'/home/me/slamprep/build/slamprep'`.
bool namesSlamprep(std::string word) {
  std::erase(word, '\'');
  return word == "slamprep" || word.ends_with("/slamprep");
}

/// One mention: a flag, the commands it may belong to, where.
struct Mention {
  std::string flag;
  std::vector<std::string> commands;
  std::string file;
  int line = 0;
};

class DocScanner {
 public:
  DocScanner(std::string file, std::vector<Mention>& out) : file_(std::move(file)), out_(out) {}

  void line(const std::string& text, int number) {
    line_ = number;
    if (text.starts_with("```")) {
      fenced_ = !fenced_;
      continued_.clear();
      return;
    }
    if (fenced_) return codeLine(text);
    if (text.starts_with("#")) {  // a heading: a new section, named by its commands
      section_ = commandsNamedIn(text);
      return;
    }
    static const std::regex span("`([^`]+)`");
    for (auto it = std::sregex_iterator(text.begin(), text.end(), span);
         it != std::sregex_iterator(); ++it)
      codeSpan((*it)[1]);
  }

 private:
  static std::vector<std::string> commandsNamedIn(const std::string& text) {
    std::vector<std::string> out;
    const auto w = words(std::regex_replace(text, std::regex("[`(),]"), " "));
    for (std::size_t i = 0; i + 1 < w.size(); ++i)
      if (namesSlamprep(w[i]) && isCommand(w[i + 1])) out.push_back(w[i + 1]);
    return out;
  }

  // A usage line sets the section's command; indented `[--flag ...]` lines continue it.
  void codeLine(const std::string& text) {
    const auto w = words(text);
    if (!continued_.empty() && !text.empty() && (text[0] == ' ') && !w.empty() &&
        w[0].starts_with("[")) {
      for (const auto& word : w) record(word, continued_);
      return;
    }
    continued_ = scan(w);
    if (!continued_.empty() && section_.empty()) section_ = continued_;
  }

  void codeSpan(const std::string& text) {
    const auto w = words(text);
    if (w.empty()) return;
    if (w[0].starts_with("--")) {  // an option on its own: the section's command
      if (section_.empty()) return;
      for (const auto& word : w) {
        if (word == "|" || word == "&&" || word == ";") break;
        record(word, section_);
      }
      return;
    }
    if (isCommand(w[0])) {  // `deskew --geometry FILE`
      std::vector<std::string> rest(w.begin() + 1, w.end());
      for (const auto& word : rest) {
        if (word == "|" || word == "&&" || word == ";") break;
        record(word, {w[0]});
      }
      return;
    }
    scan(w);
  }

  // `... slamprep CMD --a --b | other --c`: --a and --b belong to CMD, and so do the
  // alternatives of a usage line (`[--geometry G | --calibration F]`). Returns the last CMD.
  std::vector<std::string> scan(const std::vector<std::string>& w) {
    std::vector<std::string> command;
    long depth = 0;  // inside [...]: '|' separates alternatives, not commands
    for (std::size_t i = 0; i < w.size(); ++i) {
      depth +=
          std::count(w[i].begin(), w[i].end(), '[') - std::count(w[i].begin(), w[i].end(), ']');
      if (depth <= 0 && (w[i] == "|" || w[i] == "&&" || w[i] == ";" || w[i] == "||")) {
        command.clear();
      } else if (namesSlamprep(w[i]) && i + 1 < w.size() && isCommand(w[i + 1])) {
        command = {w[++i]};
      } else if (!command.empty()) {
        record(w[i], command);
      }
    }
    return command;
  }

  void record(const std::string& word, const std::vector<std::string>& commands) {
    for (const std::string& flag : flagsIn(word)) out_.push_back({flag, commands, file_, line_});
  }

  std::string file_;
  std::vector<Mention>& out_;
  bool fenced_ = false;
  int line_ = 0;
  std::vector<std::string> section_;    // commands the current section is about
  std::vector<std::string> continued_;  // the command of the previous code-block line
};

std::vector<Mention> mentions() {
  const fs::path root = SLAMPREP_SOURCE_DIR;
  std::vector<fs::path> files = {root / "README.md"};
  for (const auto& entry : fs::directory_iterator(root / "docs"))
    if (entry.path().extension() == ".md") files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  std::vector<Mention> out;
  for (const fs::path& file : files) {
    std::ifstream in(file);
    DocScanner scanner(fs::relative(file, root).string(), out);
    int number = 0;
    for (std::string text; std::getline(in, text);) scanner.line(text, ++number);
  }
  return out;
}

TEST(DocsFlags, EveryFlagTheDocsGiveACommandIsInItsHelp) {
  std::map<std::string, Flags> help;
  for (const std::string& command : kCommands) {
    help[command] = helpFlags(command);
    ASSERT_TRUE(help[command].contains("--help")) << command;
  }
  // score's options belong to its subcommands: the docs name them as `slamprep score ...`.
  for (const char* sub : {"relations", "ape", "rpe"})
    help["score"].merge(helpFlags(std::string("score ") + sub));
  const std::vector<Mention> all = mentions();
  std::map<std::string, int> checked;
  for (const Mention& m : all) {
    bool found = false;
    for (const std::string& command : m.commands) found = found || help[command].contains(m.flag);
    std::string names;
    for (const std::string& command : m.commands) names += (names.empty() ? "" : " or ") + command;
    EXPECT_TRUE(found) << m.file << ":" << m.line << ": " << m.flag << " is not an option of "
                       << "`slamprep " << names << "` (not in its --help)";
    for (const std::string& command : m.commands) ++checked[command];
  }
  // The scan must see the usage of every command with options, or it checks nothing.
  for (const std::string& command : kCommands) {
    if (help[command].size() <= 1) continue;  // plot: --help only
    EXPECT_GT(checked[command], 0) << "no flag of " << command << " found in the docs";
  }
  if (std::getenv("SLAMPREP_DOCS_FLAGS_VERBOSE"))
    for (const Mention& m : all) std::cout << m.file << ":" << m.line << " " << m.flag << "\n";
}

}  // namespace
