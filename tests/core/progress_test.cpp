// Progress lines with a fake clock: what a CI log shows, throttled, and the bar on a terminal.
#include "slamprep/core/progress.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "slamprep/core/stage_report.hpp"

namespace slamprep {
namespace {

struct Fake {
  double now = 0.0;
  std::vector<std::string> lines;
  Progress make(std::size_t total, ProgressOptions options) {
    return Progress(
        total, "trials", std::move(options), [this](const std::string& s) { lines.push_back(s); },
        [this] { return now; });
  }
};

StageEvent event(const std::string& task, const std::string& stage, int index,
                 StageEvent::Kind kind, double fraction = 0.0) {
  return {task, stage, index, 2, kind, fraction};
}

TEST(Progress, PlainLinesAtStageStartAndFinishThrottledWithEta) {
  Fake f;
  Progress p = f.make(2, {.style = ProgressStyle::kLines, .label = "bench"});
  p.stage(event("t1", "simulate", 0, StageEvent::kStart));
  f.now = 0.5;
  p.stage(event("t1", "simulate", 0, StageEvent::kUpdate, 0.5));  // no line: not a heartbeat
  f.now = 3.0;
  p.stage(event("t1", "simulate", 0, StageEvent::kFinish));
  f.now = 3.2;
  p.stage(event("t1", "deskew", 1, StageEvent::kStart));  // 0.2 s after the last line: dropped
  f.now = 15.0;
  p.stage(event("t1", "deskew", 1, StageEvent::kUpdate, 0.5));  // 12 s without a line
  f.now = 20.0;
  p.advance(1, "t1");
  f.now = 30.0;
  p.tick();  // 10 s without a line: a heartbeat
  f.now = 30.5;
  p.tick();
  f.now = 40.0;
  p.advance(1, "t2");  // the last one always shows
  p.finish("");
  const std::vector<std::string> expected = {
      "bench: t1 simulate started; 0/2 trials, 0%, elapsed 0:00, ETA ?\n",
      // (0 + 1) stages of 2 of one trial of 2: 25 %, 3 s so far -> 9 s to go.
      "bench: t1 simulate done in 3.0 s; 0/2 trials, 25%, elapsed 0:03, ETA 0:09\n",
      "bench: t1 deskew 50%; 0/2 trials, 37%, elapsed 0:15, ETA 0:25\n",
      "bench: t1 done; 1/2 trials, 50%, elapsed 0:20, ETA 0:20\n",
      "bench: t1 done; 1/2 trials, 50%, elapsed 0:30, ETA 0:30\n",
      "bench: t2 done; 2/2 trials, 100%, elapsed 0:40, ETA 0:00\n"};
  EXPECT_EQ(f.lines, expected);
}

TEST(Progress, CommandsStayQuietWhileShort) {
  Fake f;
  Progress p = f.make(1, {.style = ProgressStyle::kLines, .label = "deskew", .quiet_for_s = 2.0});
  p.stage(event("vicp", "deskew", 0, StageEvent::kStart));
  f.now = 1.0;
  p.advance(1, "vicp");
  p.finish("");
  EXPECT_TRUE(f.lines.empty());

  Fake g;
  Progress q = g.make(1, {.style = ProgressStyle::kLines, .label = "deskew", .quiet_for_s = 2.0});
  q.stage(event("vicp", "deskew", 0, StageEvent::kStart));
  g.now = 12.0;
  q.tick();
  ASSERT_EQ(g.lines.size(), 1u);
  EXPECT_EQ(g.lines[0], "deskew: vicp deskew started; 0/1 trials, 0%, elapsed 0:12, ETA ?\n");
}

TEST(Progress, BarRedrawsOneLineInPlace) {
  Fake f;
  Progress p = f.make(1, {.style = ProgressStyle::kBar});
  f.now = 4.0;
  p.stage({"t1", "match", 1, 4, StageEvent::kUpdate, 1.0});  // 2 of 4 stages: half done
  p.finish("");
  ASSERT_EQ(f.lines.size(), 3u);
  EXPECT_EQ(f.lines[0].substr(0, 2), "\r[");
  EXPECT_EQ(f.lines[1],
            "\r[###############...............] 0/1 trials, 50%, elapsed 0:04, ETA 0:04  "
            "t1 match 100%\033[K");
  EXPECT_EQ(f.lines[2], "\n");
}

TEST(Progress, ClearedBarLeavesNoEmptyLine) {
  Fake f;
  Progress p = f.make(1, {.style = ProgressStyle::kBar});
  p.advance(1, "vicp");
  p.clearLine();  // before a table row goes to stdout
  p.finish("");
  ASSERT_EQ(f.lines.size(), 3u);
  EXPECT_EQ(f.lines[2], "\r\033[K");
}

TEST(Progress, SilentWritesNothing) {
  Fake f;
  Progress p = f.make(1, {.style = ProgressStyle::kSilent});
  p.stage(event("t1", "simulate", 0, StageEvent::kStart));
  p.advance(1, "t1");
  p.finish("done");
  EXPECT_TRUE(f.lines.empty());
}

TEST(StageReport, EventsSurviveThePipeEncoding) {
  const StageEvent e{"default-0003", "calibrate", 2, 4, StageEvent::kUpdate, 0.25};
  StageEvent back;
  ASSERT_TRUE(
      decodeStageEvent(encodeStageEvent(e).substr(0, encodeStageEvent(e).size() - 1), back));
  EXPECT_EQ(back.task, e.task);
  EXPECT_EQ(back.stage, e.stage);
  EXPECT_EQ(back.index, 2);
  EXPECT_EQ(back.count, 4);
  EXPECT_EQ(back.kind, StageEvent::kUpdate);
  EXPECT_DOUBLE_EQ(back.fraction, 0.25);
  EXPECT_FALSE(decodeStageEvent("garbage", back));
}

TEST(StageReport, ReporterSendsStartUpdateFinishToTheSink) {
  std::vector<StageEvent> seen;
  {
    const ScopedStageSink sink([&](const StageEvent& e) { seen.push_back(e); });
    StageReporter stages("t1", 2);
    stages.begin("simulate");
    stages.update(0.5);
    stages.begin("deskew");  // ends simulate
  }                          // the reporter ends deskew
  ASSERT_EQ(seen.size(), 5u);
  EXPECT_EQ(seen[2].kind, StageEvent::kFinish);
  EXPECT_EQ(seen[3].stage, "deskew");
  EXPECT_EQ(seen[3].index, 1);
  EXPECT_EQ(seen[4].kind, StageEvent::kFinish);
  StageReporter orphan("t2", 1);  // no sink: reports vanish
  orphan.begin("match");
}

}  // namespace
}  // namespace slamprep
