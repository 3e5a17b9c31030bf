#pragma once
// Progress for long work: a bar with ETA on a terminal, occasional plain lines otherwise.

#include <chrono>
#include <cstdio>
#include <string>

namespace slamprep::eval {

class Progress {
 public:
  /// `total` units of work named `unit` ("trials"); draws on `out` (stderr by default; null:
  /// silent).
  Progress(std::size_t total, std::string unit, std::FILE* out = stderr);
  /// Marks `n` more units done; `note` (e.g. the last trial's id) is shown beside the bar.
  void advance(std::size_t n = 1, const std::string& note = "");
  /// Ends the bar with a final line.
  void finish(const std::string& message);

 private:
  void draw(const std::string& note);
  std::size_t total_;
  std::size_t done_ = 0;
  std::string unit_;
  std::FILE* out_;
  bool tty_;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_line_;
};

/// "1:05" / "12:03:07" for a duration in seconds.
std::string formatDuration(double seconds);

}  // namespace slamprep::eval
