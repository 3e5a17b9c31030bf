#include "eval/bench/progress.hpp"

#include <unistd.h>

#include <cmath>

namespace slamprep::eval {

std::string formatDuration(double seconds) {
  const long s = std::lround(std::max(0.0, seconds));
  char buf[32];
  if (s >= 3600)
    std::snprintf(buf, sizeof buf, "%ld:%02ld:%02ld", s / 3600, s / 60 % 60, s % 60);
  else
    std::snprintf(buf, sizeof buf, "%ld:%02ld", s / 60, s % 60);
  return buf;
}

Progress::Progress(std::size_t total, std::string unit, std::FILE* out)
    : total_(total),
      unit_(std::move(unit)),
      out_(out),
      tty_(out != nullptr && isatty(fileno(out)) != 0),
      start_(std::chrono::steady_clock::now()),
      last_line_(start_) {
  if (tty_) draw("");
}

void Progress::advance(std::size_t n, const std::string& note) {
  done_ += n;
  draw(note);
}

void Progress::draw(const std::string& note) {
  if (out_ == nullptr) return;
  const auto now = std::chrono::steady_clock::now();
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const double fraction = total_ ? static_cast<double>(done_) / total_ : 1.0;
  const std::string eta = done_ ? formatDuration(elapsed / done_ * (total_ - done_)) : "?";
  if (tty_) {
    constexpr int kWidth = 30;
    const int filled = static_cast<int>(fraction * kWidth);
    std::fprintf(out_, "\r[%s%s] %zu/%zu %s  elapsed %s  ETA %s  %.40s\033[K",
                 std::string(filled, '#').c_str(), std::string(kWidth - filled, '.').c_str(), done_,
                 total_, unit_.c_str(), formatDuration(elapsed).c_str(), eta.c_str(), note.c_str());
  } else if (done_ == total_ || std::chrono::duration<double>(now - last_line_).count() >= 10.0) {
    // Not a terminal (CI logs, pipes): a line every 10 s at most, and the last one.
    std::fprintf(out_, "%zu/%zu %s done (%.0f%%), elapsed %s, ETA %s\n", done_, total_,
                 unit_.c_str(), 100.0 * fraction, formatDuration(elapsed).c_str(), eta.c_str());
    last_line_ = now;
  }
  std::fflush(out_);
}

void Progress::finish(const std::string& message) {
  if (out_ == nullptr) return;
  if (tty_) std::fprintf(out_, "\n");
  if (!message.empty()) std::fprintf(out_, "%s\n", message.c_str());
  std::fflush(out_);
}

}  // namespace slamprep::eval
