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

/// Scans stamped by a host that measures each revolution's scan_time on the same clock (as
/// rplidar_ros does: the time its grab of a revolution took): their steps alternate 0.1231 and
/// 0.1350 s, now and then 0.1350 twice (a TurtleBot4's RPLIDAR), and each scan_time is its step.
std::vector<ScanRecord> hostScans() {
  std::vector<ScanRecord> out;
  double stamp = 10.0;
  for (int k = 0; k < 300; ++k) {
    const double step = (k % 2 || k % 16 == 0) ? 0.1350 : 0.1231;
    ScanRecord r;
    r.scan.stamp_s = stamp;
    r.scan.scan_time_s = step;
    out.push_back(r);
    stamp += step;
  }
  return out;
}

Dataset withStreams(std::vector<EncoderSample> e, std::vector<ScanRecord> s) {
  Dataset d;
  d.encoders = std::move(e);
  for (const EncoderSample& x : d.encoders) d.odom_nominal.push_back(x.stamp_s, SE2());
  d.scans = std::move(s);
  return d;
}

// regularizeStamps leaves stamps alone that their ticks say are right, the odometry stamped with
// the encoders alike, and still moves host-stamped encoders. Scans whose scan_time follows their
// steps are moved all the same: that scan_time was measured on the clock that stamped them.
TEST(DatasetStamps, KeepsStampsTheirTicksSayAreRight) {
  Dataset right = withStreams(encoders(0.007, 0.0, 2), hostScans());
  const Dataset before = right;
  const std::vector<StreamStamps> streams = regularizeStamps(right);
  ASSERT_EQ(streams.size(), 3u);
  for (const StreamStamps& s : streams) {
    if (s.stream == "scans") {
      EXPECT_TRUE(s.applied);
      EXPECT_FALSE(s.stamped_right);
      continue;
    }
    EXPECT_FALSE(s.applied) << s.stream;
    EXPECT_TRUE(s.stamped_right) << s.stream;
    EXPECT_NE(s.reason.find("stamped right: their ticks bound"), std::string::npos) << s.reason;
    EXPECT_GT(s.residual_rms_s, 0.004) << s.stream;  // how irregularly it was sampled
  }
  EXPECT_NE(stampsSummary(streams).find("stamps: encoders kept as stamped right: their ticks"),
            std::string::npos)
      << stampsSummary(streams);
  for (std::size_t k = 0; k < right.encoders.size(); ++k)
    ASSERT_EQ(right.encoders[k].stamp_s, before.encoders[k].stamp_s);

  Dataset host = withStreams(encoders(0.0, 0.007, 2), hostScans());
  for (const StreamStamps& s : regularizeStamps(host)) {
    EXPECT_TRUE(s.applied) << s.stream;
    EXPECT_FALSE(s.stamped_right) << s.stream;
  }
}

}  // namespace
}  // namespace slamprep::algo
