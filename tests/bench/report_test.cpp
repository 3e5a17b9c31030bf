#include "slamprep/eval/bench/report.hpp"

#include <gtest/gtest.h>

namespace slamprep::eval {
namespace {

MetricStats stats(std::size_t n, double mean, double std) {
  return {.n = n, .mean = mean, .std = std, .min = mean, .max = mean};
}

SuiteSummary summaryWith(double joint_b_pct, double linear_mean_m) {
  SuiteSummary s;
  s.trials = 2;
  s.metrics = {{"calibration/joint/abs_error/b_pct", stats(2, joint_b_pct, 0.01)},
               {"calibration/joint/ok", stats(2, 1.0, 0.0)},
               {"deskew/odom-linear/mean_m", stats(1, linear_mean_m, 0.0)}};
  return s;
}

TEST(Report, TablesShowEveryMethodWithUnits) {
  Suite suite;
  suite.name = "demo";
  suite.worlds = {"w"};
  suite.scenarios = {"s"};
  const std::string md = renderReport(suite, summaryWith(0.042, 0.00123), {"deskew.png"});
  EXPECT_NE(md.find("# Suite `demo`"), std::string::npos);
  EXPECT_NE(md.find("| joint | 100 % |"), std::string::npos) << md;
  EXPECT_NE(md.find("0.042 ± 0.01"), std::string::npos) << md;
  EXPECT_NE(md.find("| odom-linear | - | 1.23 |"), std::string::npos) << md;  // metres -> mm
  EXPECT_NE(md.find("![deskew.png](plots/deskew.png)"), std::string::npos);
}

TEST(Report, RefusedScansAreCountedByReason) {
  SuiteSummary summary = summaryWith(0.042, 0.00123);
  auto& m = summary.metrics;
  EXPECT_EQ(renderConsoleSummary(summary).find("refused"), std::string::npos);  // none refused
  // Two trials refused 3 and 5 scans: 6 not-bracketed, 2 with a gap.
  m["deskew/odom-linear/refused_scans"] = stats(2, 4.0, 1.41);
  m["deskew/odom-linear/refused_by_reason/not-bracketed"] = stats(2, 3.0, 0);
  m["deskew/odom-linear/refused_by_reason/sample-gap"] = stats(1, 2.0, 0);
  const std::string expected =
      "odom-linear: 8 scans refused in 2 trial(s) (not-bracketed 6, sample-gap 2)";
  EXPECT_NE(renderConsoleSummary(summary).find("refused: " + expected), std::string::npos)
      << renderConsoleSummary(summary);
  Suite suite;
  EXPECT_NE(renderReport(suite, summary, {}).find("- " + expected), std::string::npos);
}

TEST(Report, IsAFunctionOfTheSummaryAlone) {
  Suite suite;
  suite.name = "demo";
  EXPECT_EQ(renderReport(suite, summaryWith(1, 2), {}), renderReport(suite, summaryWith(1, 2), {}));
  EXPECT_NE(renderReport(suite, summaryWith(1, 2), {}), renderReport(suite, summaryWith(1, 3), {}));
}

}  // namespace
}  // namespace slamprep::eval
