#include "slamprep/algo/timing/stamp_checks.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "slamprep/algo/timing/dataset_stamps.hpp"

namespace slamprep::algo {
namespace {

constexpr double kTicksPerSecond = 4000.0;  // both wheels, turning steadily

/// 20 Hz encoders turning steadily for 60 s: sampled `sampling_s` off their grid (the ticks at
/// the time taken) and stamped `stamp_error_s` off the time taken (Gaussian sigmas).
std::vector<EncoderSample> encoders(double sampling_s, double stamp_error_s, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> sampling(0.0, sampling_s), stamp(0.0, stamp_error_s);
  std::vector<EncoderSample> out;
  for (int k = 0; k < 1200; ++k) {
    const double taken = 0.05 * k + sampling(rng);
    const auto ticks = static_cast<std::int64_t>(std::floor(kTicksPerSecond * taken));
    out.push_back({taken + stamp(rng), ticks, ticks});
  }
  return out;
}

// Eq. 1 against the truth: ticks that follow their irregular stamps bound the error near 0, a
// stamp error of 7 ms near 7 ms. Seeds 1-5: 0.075-0.081 ms (the ticks' rounding) and 7.10-7.53
// ms.
TEST(StampChecks, TicksBoundTheStampErrorNotTheSampling) {
  const std::optional<double> right = tickStampErrorBound(encoders(0.007, 0.0, 1));
  ASSERT_TRUE(right.has_value());
  EXPECT_LT(*right, 0.0005);
  const std::optional<double> wrong = tickStampErrorBound(encoders(0.0, 0.007, 1));
  ASSERT_TRUE(wrong.has_value());
  EXPECT_NEAR(*wrong, 0.007, 0.0015);
}

/// Scans whose revolutions take 0.1231 and 0.1350 s in turn, now and then 0.1350 twice (a
/// TurtleBot4's RPLIDAR), each reporting its own duration as scan_time; stamped at their start,
/// `stamp_error_s` off.
std::vector<ScanRecord> scans(double stamp_error_s, bool report_duration, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> stamp(0.0, stamp_error_s);
  std::vector<ScanRecord> out;
  double start = 10.0;
  for (int k = 0; k < 300; ++k) {
    const double duration = (k % 2 || k % 16 == 0) ? 0.1350 : 0.1231;
    ScanRecord r;
    r.scan.stamp_s = start + stamp(rng);
    r.scan.scan_time_s = report_duration ? duration : 0.1296;
    out.push_back(r);
    start += duration;
  }
  return out;
}

TEST(StampChecks, ScanStepsThatAreTheirScanTimeAreRight) {
  const std::optional<ScanTimeCheck> right = checkScanTimes(scans(0.0, true, 1));
  ASSERT_TRUE(right.has_value());
  EXPECT_EQ(right->steps, 299u);
  EXPECT_LT(right->rms_about_scan_time_s, 1e-9);
  EXPECT_NEAR(right->rms_about_period_s, 0.5 * (0.1350 - 0.1231), 1e-3);
  // A constant scan_time explains nothing of the steps.
  const std::optional<ScanTimeCheck> constant = checkScanTimes(scans(0.004, false, 1));
  ASSERT_TRUE(constant.has_value());
  EXPECT_GT(constant->rms_about_scan_time_s, 0.9 * constant->rms_about_period_s);
}

Dataset withStreams(std::vector<EncoderSample> e, std::vector<ScanRecord> s) {
  Dataset d;
  d.encoders = std::move(e);
  for (const EncoderSample& x : d.encoders) d.odom_nominal.push_back(x.stamp_s, SE2());
  d.scans = std::move(s);
  return d;
}

// regularizeStamps leaves stamps alone that their own evidence says are right, the odometry
// stamped with the encoders alike, and still moves host-stamped ones.
TEST(DatasetStamps, KeepsStampsTheirTicksAndScanTimesSayAreRight) {
  Dataset right = withStreams(encoders(0.007, 0.0, 2), scans(0.0, true, 2));
  const Dataset before = right;
  const std::vector<StreamStamps> kept = regularizeStamps(right);
  ASSERT_EQ(kept.size(), 3u);
  for (const StreamStamps& s : kept) {
    EXPECT_FALSE(s.applied) << s.stream;
    EXPECT_TRUE(s.stamped_right) << s.stream;
    EXPECT_NE(s.reason.find("stamped right"), std::string::npos) << s.reason;
    EXPECT_GT(s.residual_rms_s, 0.004) << s.stream;  // how irregularly it was sampled
  }
  EXPECT_NE(stampsSummary(kept).find("stamps: scans kept as stamped right: their steps are"),
            std::string::npos)
      << stampsSummary(kept);
  for (std::size_t k = 0; k < right.encoders.size(); ++k)
    ASSERT_EQ(right.encoders[k].stamp_s, before.encoders[k].stamp_s);
  for (std::size_t k = 0; k < right.scans.size(); ++k)
    ASSERT_EQ(right.scans[k].scan.stamp_s, before.scans[k].scan.stamp_s);

  Dataset host = withStreams(encoders(0.0, 0.007, 2), scans(0.004, false, 2));
  for (const StreamStamps& s : regularizeStamps(host)) {
    EXPECT_TRUE(s.applied) << s.stream;
    EXPECT_FALSE(s.stamped_right) << s.stream;
  }
}

}  // namespace
}  // namespace slamprep::algo
