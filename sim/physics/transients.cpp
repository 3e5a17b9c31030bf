#include "slamprep/sim/physics/transients.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "slamprep/core/error.hpp"
#include "slamprep/core/input_file.hpp"

namespace slamprep::sim {
namespace {

constexpr const char* kHeader = "from_s,to_s,x_m,y_m,radius_m";

Transient parseLine(const std::string& line, const std::string& where) {
  Transient t;
  double* fields[] = {&t.from_s, &t.to_s, &t.center_m.x(), &t.center_m.y(), &t.radius_m};
  std::size_t at = 0;
  for (std::size_t k = 0; k < 5; ++k) {
    const std::size_t end = k < 4 ? line.find(',', at) : line.size();
    if (end == std::string::npos) throw InputError(where, "expected 5 comma-separated numbers");
    const std::string cell = line.substr(at, end - at);
    char* stop = nullptr;
    *fields[k] = std::strtod(cell.c_str(), &stop);
    if (cell.empty() || *stop != '\0' || !std::isfinite(*fields[k]))
      throw InputError(where, "'" + cell + "' is not a finite number");
    at = end + 1;
  }
  if (!(t.from_s <= t.to_s)) throw InputError(where, "from_s must not exceed to_s");
  if (!(t.radius_m > 0.0 && t.radius_m <= 10.0))
    throw InputError(where, "radius_m must be in (0, 10]");
  return t;
}

}  // namespace

std::vector<Transient> loadTransients(const std::filesystem::path& file) {
  std::istringstream in(readInputFile(file, "transients file", kMaxRecordFileBytes));
  std::string line;
  std::size_t number = 0;
  std::vector<Transient> out;
  while (std::getline(in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::string where = file.string() + ":" + std::to_string(number);
    if (number == 1) {
      if (line != kHeader) throw InputError(where, std::string("expected the header ") + kHeader);
      continue;
    }
    if (!line.empty()) out.push_back(parseLine(line, where));
  }
  if (number == 0) throw InputError(file.string(), std::string("expected the header ") + kHeader);
  return out;
}

std::string transientsCsv(const std::vector<Transient>& transients) {
  std::string out = std::string(kHeader) + "\n";
  char line[160];
  for (const Transient& t : transients) {
    std::snprintf(line, sizeof line, "%.4f,%.4f,%.4f,%.4f,%.4f\n", t.from_s, t.to_s, t.center_m.x(),
                  t.center_m.y(), t.radius_m);
    out += line;
  }
  return out;
}

std::optional<double> rayDisc(const Eigen::Vector2d& p, const Eigen::Vector2d& d,
                              const Eigen::Vector2d& c, double r) {
  const Eigen::Vector2d pc = c - p;
  const double along = pc.dot(d);
  const double miss_sq = pc.squaredNorm() - along * along;
  if (miss_sq > r * r || pc.squaredNorm() <= r * r) return std::nullopt;
  const double s = along - std::sqrt(r * r - miss_sq);
  return s > 0.0 ? std::optional<double>(s) : std::nullopt;
}

TransientCaster::TransientCaster(std::vector<Transient> transients)
    : by_start_(std::move(transients)) {
  std::stable_sort(by_start_.begin(), by_start_.end(),
                   [](const Transient& a, const Transient& b) { return a.from_s < b.from_s; });
  for (const Transient& t : by_start_) longest_s_ = std::max(longest_s_, t.to_s - t.from_s);
}

std::optional<double> TransientCaster::castRay(const Eigen::Vector2d& origin,
                                               const Eigen::Vector2d& dir, double t_s,
                                               double max_range_m) {
  if (t_s < last_t_s_) {  // stepped back: those that began since may not have, and some ended
    present_.clear();
    const auto first =
        std::partition_point(by_start_.begin(), by_start_.end(), [&](const Transient& t) {
          return t.from_s < t_s - longest_s_;  // began before the longest could last: over
        });
    next_ = static_cast<std::size_t>(first - by_start_.begin());
  }
  last_t_s_ = t_s;
  for (; next_ < by_start_.size() && by_start_[next_].from_s <= t_s; ++next_)
    present_.push_back(next_);
  std::erase_if(present_, [&](std::size_t i) { return by_start_[i].to_s < t_s; });
  std::optional<double> nearest;
  for (std::size_t i : present_) {
    const Transient& t = by_start_[i];
    if (const auto s = rayDisc(origin, dir, t.center_m, t.radius_m);
        s && *s <= max_range_m && (!nearest || *s < *nearest))
      nearest = s;
  }
  return nearest;
}

}  // namespace slamprep::sim
