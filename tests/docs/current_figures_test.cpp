// The figures the docs call current are the committed ones. A page marks such a figure with an
// HTML comment right after it, invisible once rendered:
//
//   mean NEES 6.41<!-- current: results/seeds/summary.json#/metrics/calibration~1joint~1nees/mean
//   -->
//
// The path is relative to the repository root, the part after '#' a JSON pointer (RFC 6901: a
// '/' inside a key is written "~1"), and an optional factor (` x1000`) scales the value first
// (metres written as millimetres). The number just before the marker, rounded as written (6.41:
// two decimals), must be the value there: editing either the page or the result fails the test.
// A marker inside code (a code span or a fenced block) is an example, not a figure.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
const fs::path kRoot = SLAMPREP_SOURCE_DIR;

std::string slurp(const fs::path& file) {
  std::ifstream in(file);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// One marker: where it is, the figure written before it, and what it points to.
struct Marker {
  std::string where;    ///< "docs/design.md:123"
  std::string written;  ///< "6.41", empty when no number precedes the marker
  std::string file;     ///< "results/seeds/summary.json"
  std::string pointer;  ///< "/metrics/calibration~1joint~1nees/mean"
  double scale = 1.0;
};

const std::regex& markerPattern() {
  static const std::regex re(R"(<!--\s*current:\s*([^#\s]+)#(\S*)(?:\s+x([0-9.eE+-]+))?\s*-->)");
  return re;
}

/// The number that ends `prefix` (blanks allowed after it): "+0.23", "-0.09", "154".
std::string trailingNumber(const std::string& prefix) {
  static const std::regex number(R"(([+-]?[0-9]+(?:\.[0-9]+)?)\s*$)");
  std::smatch m;
  return std::regex_search(prefix, m, number) ? m[1].str() : "";
}

/// Whether position `at` of `line` is inside a code span (an odd number of backticks before it).
bool insideCodeSpan(const std::string& line, std::size_t at) {
  return std::count(line.begin(), line.begin() + static_cast<std::ptrdiff_t>(at), '`') % 2 == 1;
}

/// Every marker of `text` (a page named `name`).
std::vector<Marker> markersIn(const std::string& text, const std::string& name) {
  std::vector<Marker> out;
  std::istringstream lines(text);
  int number = 0;
  bool fenced = false;
  for (std::string line; std::getline(lines, line);) {
    ++number;
    if (line.starts_with("```")) fenced = !fenced;
    if (fenced) continue;
    for (auto it = std::sregex_iterator(line.begin(), line.end(), markerPattern());
         it != std::sregex_iterator(); ++it) {
      const std::smatch& m = *it;
      if (insideCodeSpan(line, m.position(0))) continue;
      Marker marker{name + ":" + std::to_string(number),
                    trailingNumber(line.substr(0, m.position(0))), m[1], m[2]};
      if (m[3].matched) marker.scale = std::stod(m[3]);
      out.push_back(marker);
    }
  }
  return out;
}

/// Digits after the decimal point of a written number.
int decimalsOf(const std::string& written) {
  const auto dot = written.find('.');
  return dot == std::string::npos ? 0 : static_cast<int>(written.size() - dot - 1);
}

/// "" when the marker's figure is the committed value rounded as written, else why not.
std::string check(const Marker& marker, const fs::path& root) {
  const std::string at = marker.where + ": " + marker.file + "#" + marker.pointer;
  if (marker.written.empty()) return at + ": no number right before the marker";
  if (!fs::is_regular_file(root / marker.file)) return at + ": no such file";
  const auto json = nlohmann::json::parse(slurp(root / marker.file), nullptr, false);
  if (json.is_discarded()) return at + ": not JSON";
  nlohmann::json::json_pointer pointer;
  try {
    pointer = nlohmann::json::json_pointer(marker.pointer);
  } catch (const nlohmann::json::exception&) {
    return at + ": not a JSON pointer";
  }
  if (!json.contains(pointer) || !json.at(pointer).is_number()) return at + ": not a number there";
  const double value = json.at(pointer).get<double>() * marker.scale;
  const double half_unit = 0.5 * std::pow(10.0, -decimalsOf(marker.written));
  if (std::abs(value - std::stod(marker.written)) <= half_unit * (1.0 + 1e-9)) return "";
  std::ostringstream why;
  why.precision(10);
  why << at << ": the page says " << marker.written << ", the file " << value;
  return why.str();
}

std::vector<std::string> failures(const std::vector<Marker>& markers, const fs::path& root) {
  std::vector<std::string> out;
  for (const Marker& m : markers)
    if (auto why = check(m, root); !why.empty()) out.push_back(why);
  return out;
}

/// README.md and every page of docs/, with their markers.
std::vector<Marker> allMarkers() {
  std::vector<fs::path> pages = {"README.md"};
  for (const auto& entry : fs::directory_iterator(kRoot / "docs"))
    if (entry.path().extension() == ".md") pages.push_back(fs::relative(entry.path(), kRoot));
  std::vector<Marker> out;
  for (const auto& page : pages) {
    const auto found = markersIn(slurp(kRoot / page), page.generic_string());
    out.insert(out.end(), found.begin(), found.end());
  }
  return out;
}

std::string joined(const std::vector<std::string>& lines) {
  std::string out;
  for (const auto& l : lines) out += l + "\n";
  return out;
}

TEST(DocsCurrentFigures, EveryMarkedFigureIsTheCommittedOne) {
  const auto markers = allMarkers();
  const auto bad = failures(markers, kRoot);
  EXPECT_TRUE(bad.empty()) << bad.size() << " of " << markers.size()
                           << " marked figures differ from the committed results:\n"
                           << joined(bad);
}

// The design page's consistency figures are the ones most often re-measured: they stay marked.
TEST(DocsCurrentFigures, TheDesignPageMarksTheSeedsSuitesNees) {
  int nees = 0;
  for (const Marker& m : markersIn(slurp(kRoot / "docs/design.md"), "docs/design.md"))
    if (m.file == "results/seeds/summary.json" && m.pointer.ends_with("nees_mean")) ++nees;
  EXPECT_EQ(nees, 2) << "joint's and Ceres' mean NEES";
}

// The check itself: a number changed on the page, a changed scale, a missing key or file, a
// marker without a number, each is reported; the committed value rounded as written is not.
TEST(DocsCurrentFigures, AChangedFigureOrTargetIsReported) {
  const std::string target = "results/seeds/summary.json#/metrics/calibration~1joint~1nees/mean";
  const auto json = nlohmann::json::parse(slurp(kRoot / "results/seeds/summary.json"));
  const double nees =
      json.at(nlohmann::json::json_pointer("/metrics/calibration~1joint~1nees/mean")).get<double>();
  char right[32], wrong[32], scaled[32];
  std::snprintf(right, sizeof right, "%.2f", nees);
  std::snprintf(wrong, sizeof wrong, "%.2f", nees + 0.01);
  std::snprintf(scaled, sizeof scaled, "%.0f", nees * 1000.0);
  const auto count = [](const std::string& text) {
    return failures(markersIn(text, "page.md"), kRoot).size();
  };
  EXPECT_EQ(count(std::string("NEES ") + right + "<!-- current: " + target + " -->"), 0u);
  EXPECT_EQ(count(std::string("NEES ") + wrong + " <!-- current: " + target + " -->"), 1u);
  EXPECT_EQ(count(std::string("NEES ") + scaled + "<!-- current: " + target + " x1000 -->"), 0u);
  EXPECT_EQ(count(std::string("NEES ") + right + "<!-- current: " + target + " x1000 -->"), 1u);
  EXPECT_EQ(count(std::string("NEES ") + right + "<!-- current: " + target + "_typo -->"), 1u);
  EXPECT_EQ(count(std::string("NEES ") + right + "<!-- current: results/none.json#/a -->"), 1u);
  EXPECT_EQ(count("NEES<!-- current: " + target + " -->"), 1u);
  EXPECT_EQ(count("an example: `1.5<!-- current: " + target + " -->`"), 0u);
  EXPECT_EQ(count("```\n1.5<!-- current: " + target + " -->\n```"), 0u);
}

}  // namespace
