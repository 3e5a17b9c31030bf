// The rules the suite figures keep (docs/plots.md): no bars, one panel or row per condition
// (never pooled), lines only along a scenario series, error bars only from repeated seeds,
// legends beside the data, panel titles in words.
#include <gtest/gtest.h>

#include <cmath>

#include "slamprep/eval/bench/figure_groups.hpp"
#include "slamprep/eval/bench/figures_internal.hpp"

namespace slamprep::eval {
namespace {

MetricStats stat(double mean, double std) {
  // An uneven spread, so a whisker from min to max differs from ±1σ.
  return {.n = 1, .mean = mean, .std = std, .min = mean - std, .max = mean + 2 * std};
}

// A group of `seeds` trials: calibration errors for joint (with mount) and model (without),
// de-skew errors for none and odom-linear, and the measured mean speed.
SummaryGroup group(const std::string& scenario, std::map<std::string, std::string> sweep,
                   std::size_t seeds, double scale) {
  SummaryMetrics m;
  for (const char* p : {"r_L_pct", "r_R_pct", "b_pct", "lidar_x_mm", "lidar_y_mm", "lidar_yaw_deg"})
    m[std::string("calibration/joint/abs_error/") + p] = stat(0.05 * scale, 0.01);
  for (const char* p : {"r_L_pct", "r_R_pct", "b_pct"})
    m[std::string("calibration/model/abs_error/") + p] = stat(0.2 * scale, 0.03);
  m["calibration/joint/ok"] = m["calibration/model/ok"] = stat(1, 0);
  m["deskew/none/mean_m"] = stat(0.1 * scale, 0.01);
  m["deskew/odom-linear/mean_m"] = stat(0.005 * scale, 0.001);
  m["sim/mean_speed_mps"] = stat(scale, 0.0);
  return {.world = "worlds/room.yaml",
          .scenario = scenario,
          .sweep = std::move(sweep),
          .trials = seeds,
          .metrics = m,
          .consistency = {}};
}

bool anyBars(const plot::Figure& f) {
  for (const auto& a : f.axes)
    for (const auto& s : a.series)
      if (s.style == plot::Style::Bars) return true;
  return false;
}

TEST(Figures, CalibrationHasARowPerConditionAndBarsOfSigmaOnlyFromSeeds) {
  const std::vector<SummaryGroup> groups = {group("worlds/scenarios/default.yaml", {}, 1, 1.0),
                                            group("worlds/scenarios/arc.yaml", {}, 5, 2.0)};
  const plot::Figure f = calibrationFigure(groups);
  ASSERT_EQ(f.axes.size(), 6u);  // two rows of three panels: nothing pooled
  EXPECT_FALSE(anyBars(f));
  EXPECT_EQ(f.axes[0].title, "Calibration drive (1 seed)");
  EXPECT_EQ(f.axes[3].title, "Circle arc, 1 m/s (mean, min to max over 5 seeds)");
  EXPECT_EQ(f.axes[0].legend, plot::LegendPosition::Outside);
  for (const auto& s : f.axes[0].series)
    for (double e : s.y_err) EXPECT_EQ(e, 0.0);  // one seed: no spread to show
  for (const auto& s : f.axes[3].series) {
    for (double e : s.y_err) EXPECT_GT(e, 0.0);
    // Whiskers span min..max of the seeds: never below zero on the log axis.
    ASSERT_EQ(s.y_err_low.size(), s.y.size());
    for (std::size_t k = 0; k < s.y.size(); ++k) {
      EXPECT_NEAR(s.y_err[k], 2 * s.y_err_low[k], 1e-12);
      EXPECT_GT(s.y[k] - s.y_err_low[k], 0.0);
    }
  }
  // Each row shows its own condition's values, not a mean over both.
  EXPECT_DOUBLE_EQ(f.axes[0].series[0].y[0], 0.05);
  EXPECT_DOUBLE_EQ(f.axes[3].series[0].y[0], 0.10);
  // Mount panels only have the methods that estimate a mount.
  ASSERT_EQ(f.axes[1].series.size(), 1u);
  EXPECT_EQ(f.axes[1].series[0].label, "joint");
}

// `n` seeds of signed errors, spread evenly: joint near zero, model biased by -0.16 %, direct's
// wheel radii 7 % off (its track width is not).
TrialRows seedRows(int n) {
  TrialRows rows;
  for (int k = 0; k < n; ++k) {
    const double u = (k - (n - 1) / 2.0) / n;  // within (-0.5, 0.5)
    auto& row = rows.emplace_back();
    for (const char* p :
         {"r_L_pct", "r_R_pct", "b_pct", "lidar_x_mm", "lidar_y_mm", "lidar_yaw_deg"})
      row[std::string("calibration/joint/signed_error/") + p] = 0.05 * u;
    for (const char* p : {"r_L_pct", "r_R_pct", "b_pct"})
      row[std::string("calibration/model/signed_error/") + p] = -0.16 + 0.02 * u;
    row["calibration/direct/signed_error/r_L_pct"] = 6.9 + 0.1 * u;
    row["calibration/direct/signed_error/r_R_pct"] = -7.8 + 0.1 * u;
    row["calibration/direct/signed_error/b_pct"] = 0.1 + 0.05 * u;
  }
  return rows;
}

SummaryGroup groupWithDirect(int seeds) {
  SummaryGroup g = group("worlds/scenarios/calibration_3min.yaml", {}, seeds, 1.0);
  g.metrics["calibration/direct/ok"] = stat(1, 0);
  g.metrics["calibration/direct/abs_error/b_pct"] = stat(0.1, 0.02);
  return g;
}

const plot::Series* seriesOf(const plot::Axes& axes, const std::string& method) {
  for (const auto& s : axes.series)
    if (s.label == method) return &s;
  return nullptr;
}

TEST(Figures, ManySeedsGiveBoxPlotsOfTheSignedErrorAndOffScaleBoxesTheirOwnPanel) {
  const int seeds = kMinSeedsForBoxes;
  const plot::Figure f = calibrationFigure({groupWithDirect(seeds)}, {seedRows(seeds)});
  EXPECT_NE(f.title.find("10 seeds"), std::string::npos) << f.title;
  ASSERT_EQ(f.axes.size(), 4u);  // wheel geometry, direct's radii, mount position, mount yaw
  EXPECT_EQ(f.cols, 4);
  for (const auto& a : f.axes) {
    EXPECT_FALSE(a.log_y);  // signed values: linear
    ASSERT_EQ(a.segments.size(), 1u);
    EXPECT_EQ(a.segments[0].xyxy[0][1], 0.0);  // the zero line
    EXPECT_EQ(a.segments[0].xyxy[0][3], 0.0);
    for (const auto& s : a.series) EXPECT_EQ(s.style, plot::Style::Box);
  }
  EXPECT_EQ(f.axes[0].y_label, "error [%]");
  EXPECT_EQ(f.axes[0].legend, plot::LegendPosition::Outside);
  // direct's track width stays with the others; its radii, 7 % off, are on their own panel.
  const plot::Series* direct = seriesOf(f.axes[0], "direct");
  ASSERT_TRUE(direct);
  EXPECT_EQ(direct->x, std::vector<double>(seeds, 2.0));
  ASSERT_TRUE(seriesOf(f.axes[0], "model"));
  EXPECT_EQ(seriesOf(f.axes[0], "model")->y.size(), 3u * seeds);  // every seed, every parameter
  EXPECT_EQ(f.axes[1].title, "direct, off the others' scale");
  // Its own scale spans both radii, too coarse to read each box: the median is written out.
  EXPECT_EQ(f.axes[1].categories, (std::vector<std::string>{"r_{L} (median +6.9 %)",
                                                            "r_{R} (median \xE2\x88\x92"
                                                            "7.8 %)"}));
  ASSERT_EQ(f.axes[1].series.size(), 1u);
  EXPECT_NEAR(f.axes[1].series[0].y.front(), 6.9 - 0.05 * (seeds - 1) / seeds, 1e-12);
  EXPECT_EQ(f.axes[2].title, "lidar mount position");
  ASSERT_EQ(f.axes[2].series.size(), 1u);  // only joint has a mount
}

TEST(Figures, FewSeedsKeepTheMeanWithMinToMaxOnLogAxes) {
  const int seeds = kMinSeedsForBoxes - 1;
  const plot::Figure f = calibrationFigure({groupWithDirect(seeds)}, {seedRows(seeds)});
  ASSERT_EQ(f.axes.size(), 3u);
  for (const auto& a : f.axes) {
    EXPECT_TRUE(a.log_y);
    for (const auto& s : a.series) EXPECT_EQ(s.style, plot::Style::Markers);
  }
}

TEST(Figures, UnrelatedScenariosAreNotJoinedByLines) {
  const std::vector<SummaryGroup> groups = {
      group("worlds/scenarios/default.yaml", {}, 1, 1.0),
      group("worlds/scenarios/arc.yaml", {}, 1, 2.0),
      group("worlds/scenarios/random_smooth.yaml", {}, 1, 3.0)};
  EXPECT_FALSE(deskewVsSpeedFigure(groups));
  const plot::Figure f = deskewFigure(groups);
  ASSERT_EQ(f.axes.size(), 3u);
  for (const auto& a : f.axes)
    for (const auto& s : a.series) EXPECT_EQ(s.style, plot::Style::Markers);
}

TEST(Figures, AScenarioSeriesIsASweepWithOnePanelPerOtherSweepValue) {
  std::vector<SummaryGroup> groups;
  for (const char* rate : {"5", "10"})
    for (const char* v : {"0.25", "0.5", "1.0"})
      groups.push_back(group(std::string("worlds/scenarios/sweep/circle_v") + v + ".yaml",
                             {{"lidar.rate_hz", rate}}, 2, std::stod(v)));
  const auto f = deskewVsSpeedFigure(groups);
  ASSERT_TRUE(f);
  ASSERT_EQ(f->axes.size(), 2u);  // 5 Hz and 10 Hz never share a line
  EXPECT_EQ(f->axes[0].title.find("rate_hz"), std::string::npos);
  EXPECT_NE(f->axes[0].title.find("Hz"), std::string::npos);
  for (const auto& s : f->axes[0].series) {
    EXPECT_EQ(s.style, plot::Style::LineMarkers);
    EXPECT_EQ(s.x, (std::vector<double>{0.25, 0.5, 1.0}));  // along the measured speed
  }
}

TEST(Figures, ConditionsAreNamedInWords) {
  const SummaryGroup g = group("worlds/scenarios/calibration_3min.yaml",
                               {{"duration_s", "120"}, {"lidar.range_noise_m", "0.005"}}, 2, 1.0);
  EXPECT_EQ(conditionLabel(g, {g}), "120 s, range noise 5 mm");
  EXPECT_EQ(otherSweepLabel(g, "duration_s"), "range noise 5 mm");
  const SummaryGroup f =
      group("worlds/scenarios/default.yaml", {{"faults.enable", "encoder_spikes"}}, 5, 1.0);
  EXPECT_EQ(conditionLabel(f, {f}), "encoder spikes");
}

}  // namespace
}  // namespace slamprep::eval
