#pragma once
// Progress for long work on stderr, never in any result: one bar redrawn in place on a terminal,
// throttled plain lines otherwise (CI logs, pipes). Work is `total` tasks (trials, methods), each
// a few stages (simulate, match, calibrate, deskew) that report how far they are; the ETA comes
// from the fraction done, stages included (docs/results.md, "Progress").

#include <cstdio>
#include <functional>
#include <map>
#include <string>

namespace slamprep {

enum class ProgressStyle {
  kSilent,
  kBar,    ///< a terminal: one line redrawn in place
  kLines,  ///< not a terminal, or CI=true: plain lines, throttled
};
/// kSilent for null, kLines when `out` is not a terminal or CI=true is set, else kBar.
ProgressStyle progressStyleFor(std::FILE* out);

/// One report from a running task: it started, is `fraction` through, or finished a stage.
struct StageEvent {
  enum Kind { kStart, kUpdate, kFinish };
  std::string task;   ///< trial id, method name, ...
  std::string stage;  ///< simulate, match, calibrate, deskew
  int index = 0;      ///< stage number in the task, 0-based ...
  int count = 1;      ///< ... of this many, for the ETA
  Kind kind = kStart;
  double fraction = 0.0;  ///< kUpdate: how far through the stage, in [0, 1]
};

struct ProgressOptions {
  ProgressStyle style = ProgressStyle::kSilent;
  std::string label = "progress";  ///< the plain lines' prefix: the command
  double quiet_for_s = 0.0;        ///< nothing before this (commands: only when they run long)
  double line_interval_s = 1.0;    ///< kLines: at most one line per this, bar the last one
  double heartbeat_s = 10.0;       ///< kLines: a line at least this often while work runs
  double redraw_interval_s = 0.1;  ///< kBar: redraws at most this often
};

class Progress {
 public:
  using Clock = std::function<double()>;  ///< monotonic seconds
  using Writer = std::function<void(const std::string&)>;

  /// `total` tasks named `unit` ("trials"); a bar or lines on `out` as progressStyleFor() says.
  Progress(std::size_t total, std::string unit, std::FILE* out = stderr,
           std::string label = "bench");
  /// The same with every dependency given (tests: a fake clock, a string writer).
  Progress(std::size_t total, std::string unit, ProgressOptions options, Writer write, Clock clock);

  /// Marks `n` more tasks done; `note` (the task's name) is shown beside the bar.
  void advance(std::size_t n = 1, const std::string& note = "");
  /// A stage report from a running task.
  void stage(const StageEvent& event);
  /// Nothing new: redraws the bar (elapsed time), or a heartbeat line when one is due.
  void tick();
  /// Wipes the bar so a line can be printed on stdout; the next report redraws it.
  void clearLine();
  /// Ends the bar with a final line.
  void finish(const std::string& message);

 private:
  double fractionDone() const;
  std::string status(double now) const;
  void draw(double now, const std::string& text, bool force);

  std::size_t total_;
  std::size_t done_ = 0;
  std::string unit_;
  ProgressOptions options_;
  Writer write_;
  Clock clock_;
  double start_;
  double last_line_ = -1e300;
  std::map<std::string, double> running_;        ///< task -> fraction of it done
  std::map<std::string, double> stage_started_;  ///< "task/stage" -> start time
  std::string current_;                          ///< the bar's note: last task and stage
  bool drawn_ = false;
};

/// Seconds of std::chrono::steady_clock: Progress's clock.
double steadySeconds();

/// "1:05" / "12:03:07" for a duration in seconds.
std::string formatDuration(double seconds);

}  // namespace slamprep
