#include "slamprep/core/progress.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>

namespace slamprep {
namespace {}  // namespace

double steadySeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

namespace {

std::string percent(double fraction) {
  return std::to_string(static_cast<int>(std::floor(100.0 * std::clamp(fraction, 0.0, 1.0)))) + "%";
}

}  // namespace

std::string formatDuration(double seconds) {
  const long s = std::lround(std::max(0.0, seconds));
  char buf[32];
  if (s >= 3600)
    std::snprintf(buf, sizeof buf, "%ld:%02ld:%02ld", s / 3600, s / 60 % 60, s % 60);
  else
    std::snprintf(buf, sizeof buf, "%ld:%02ld", s / 60, s % 60);
  return buf;
}

ProgressStyle progressStyleFor(std::FILE* out) {
  if (out == nullptr) return ProgressStyle::kSilent;
  const char* ci = std::getenv("CI");
  const bool in_ci = ci != nullptr && std::strcmp(ci, "true") == 0;
  return !in_ci && isatty(fileno(out)) != 0 ? ProgressStyle::kBar : ProgressStyle::kLines;
}

Progress::Progress(std::size_t total, std::string unit, std::FILE* out, std::string label)
    : Progress(
          total, std::move(unit), {.style = progressStyleFor(out), .label = std::move(label)},
          [out](const std::string& text) {
            std::fputs(text.c_str(), out);
            std::fflush(out);
          },
          steadySeconds) {}

Progress::Progress(std::size_t total, std::string unit, ProgressOptions options, Writer write,
                   Clock clock)
    : total_(total),
      unit_(std::move(unit)),
      options_(std::move(options)),
      write_(std::move(write)),
      clock_(std::move(clock)),
      start_(clock_()) {
  if (options_.style == ProgressStyle::kBar && options_.quiet_for_s <= 0.0) draw(start_, "", true);
}

double Progress::fractionDone() const {
  if (total_ == 0) return 1.0;
  double partial = 0.0;
  for (const auto& [task, f] : running_) partial += f;
  return std::min(1.0, (done_ + partial) / total_);
}

// "3/10 trials, 27%, elapsed 0:12, ETA 0:33": the ETA assumes the rest goes as fast as so far.
std::string Progress::status(double now) const {
  const double elapsed = now - start_, f = fractionDone();
  const std::string eta = f > 0.0 ? formatDuration(elapsed * (1.0 - f) / f) : "?";
  return std::to_string(done_) + "/" + std::to_string(total_) + " " + unit_ + ", " + percent(f) +
         ", elapsed " + formatDuration(elapsed) + ", ETA " + eta;
}

void Progress::draw(double now, const std::string& text, bool force) {
  if (options_.style == ProgressStyle::kSilent) return;
  if (!text.empty()) current_ = text;
  if (now - start_ < options_.quiet_for_s && !(force && drawn_)) return;
  if (options_.style == ProgressStyle::kBar) {
    if (!force && now - last_line_ < options_.redraw_interval_s) return;
    constexpr int kWidth = 30;
    const int filled = static_cast<int>(fractionDone() * kWidth);
    write_("\r[" + std::string(filled, '#') + std::string(kWidth - filled, '.') + "] " +
           status(now) + "  " + current_.substr(0, 40) + "\033[K");
  } else {
    if (!force && now - last_line_ < options_.line_interval_s) return;
    write_(options_.label + ": " + (current_.empty() ? "" : current_ + "; ") + status(now) + "\n");
  }
  last_line_ = now;
  drawn_ = true;
}

void Progress::advance(std::size_t n, const std::string& note) {
  done_ += n;
  running_.erase(note);
  draw(clock_(), note.empty() ? std::string() : note + " done", done_ >= total_);
}

void Progress::stage(const StageEvent& e) {
  const double now = clock_();
  const double count = std::max(1, e.count);
  const std::string key = e.task + "/" + e.stage;
  switch (e.kind) {
    case StageEvent::kStart:
      running_[e.task] = e.index / count;
      stage_started_[key] = now;
      draw(now, e.task + " " + e.stage + " started", false);
      return;
    case StageEvent::kUpdate: {
      running_[e.task] = (e.index + std::clamp(e.fraction, 0.0, 1.0)) / count;
      const std::string text = e.task + " " + e.stage + " " + percent(e.fraction);
      // Lines: only a heartbeat while a stage runs long; the bar takes every update.
      if (options_.style == ProgressStyle::kLines && now - last_line_ < options_.heartbeat_s) {
        current_ = text;
        return;
      }
      draw(now, text, options_.style == ProgressStyle::kLines);
      return;
    }
    case StageEvent::kFinish: {
      running_[e.task] = (e.index + 1) / count;
      const auto it = stage_started_.find(key);
      char took[32];
      std::snprintf(took, sizeof took, "%.1f", it == stage_started_.end() ? 0.0 : now - it->second);
      if (it != stage_started_.end()) stage_started_.erase(it);
      draw(now, e.task + " " + e.stage + " done in " + took + " s", false);
      return;
    }
  }
}

void Progress::tick() {
  const double now = clock_();
  if (options_.style == ProgressStyle::kLines && now - last_line_ < options_.heartbeat_s) return;
  draw(now, "", options_.style == ProgressStyle::kLines);
}

void Progress::clearLine() {
  if (options_.style != ProgressStyle::kBar || !drawn_) return;
  write_("\r\033[K");
  drawn_ = false;  // nothing of the bar left for finish() to end
}

void Progress::finish(const std::string& message) {
  if (options_.style == ProgressStyle::kSilent) return;
  if (options_.style == ProgressStyle::kBar && drawn_) write_("\n");
  if (!message.empty()) write_(message + "\n");
}

}  // namespace slamprep
