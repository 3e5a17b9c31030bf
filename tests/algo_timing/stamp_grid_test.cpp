#include "slamprep/algo/timing/stamp_grid.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "slamprep/algo/timing/dataset_stamps.hpp"

namespace slamprep::algo {
namespace {

// A sensor's true sample times: period T on a clock whose rate drifts by drift_ppm over the run,
// every `drop_every`-th sample lost (0: none).
std::vector<double> trueGrid(std::size_t n, double period, double drift_ppm, int drop_every) {
  std::vector<double> t;
  double now = 3.25;
  for (std::size_t k = 0; k < n; ++k) {
    if (drop_every == 0 || k % drop_every != 7) t.push_back(now);
    now += period * (1.0 + drift_ppm * 1e-6 * k / n);
  }
  return t;
}

// Host-side stamping: Gaussian jitter cut at 0.45 periods (the simulator's stamp_jitter fault).
std::vector<double> jittered(const std::vector<double>& t, double sigma, double period,
                             unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, sigma);
  std::vector<double> out;
  for (double x : t) out.push_back(x + std::clamp(noise(rng), -0.45 * period, 0.45 * period));
  return out;
}

struct Errors {
  double rms = 0, max = 0;
};
Errors errors(const std::vector<double>& a, const std::vector<double>& b) {
  Errors e;
  for (std::size_t i = 0; i < a.size(); ++i) {
    e.rms += (a[i] - b[i]) * (a[i] - b[i]);
    e.max = std::max(e.max, std::abs(a[i] - b[i]));
  }
  e.rms = std::sqrt(e.rms / a.size());
  return e;
}

TEST(StampGrid, LeavesExactGridBitForBit) {
  const auto t = trueGrid(500, 0.1, 0.0, 0);
  const StampGrid g = fitStampGrid(t);
  EXPECT_FALSE(g.applied);
  EXPECT_EQ(g.reason, "regular already");
  EXPECT_EQ(g.stamps, t);
  EXPECT_NEAR(g.period_s, 0.1, 1e-12);
}

// 1 ms jitter on a 10 ms encoder: the fitted grid is within a tenth of the jitter of the truth.
// A local line through 201 samples of sigma 1 ms has sigma ~ 1 ms * sqrt(4 / 201) = 0.14 ms
// at its ends and 0.07 ms in the middle.
TEST(StampGrid, RecoversTheGridUnderJitterDropoutsAndDrift) {
  for (unsigned seed = 1; seed <= 5; ++seed) {
    const auto truth = trueGrid(6000, 0.01, 50.0, 40);
    const auto t = jittered(truth, 1e-3, 0.01, seed);
    const StampGrid g = fitStampGrid(t);
    ASSERT_TRUE(g.applied) << g.reason;
    EXPECT_NEAR(g.residual_rms_s, 1e-3, 0.1e-3);
    EXPECT_EQ(g.missing_samples, 6000 / 40);
    const Errors e = errors(g.stamps, truth);
    EXPECT_LT(e.rms, 0.1e-3) << "seed " << seed;
    EXPECT_LT(e.max, 0.6e-3) << "seed " << seed;
    for (std::size_t i = 1; i < g.stamps.size(); ++i) ASSERT_GT(g.stamps[i], g.stamps[i - 1]);
  }
}

// A 5 ms IMU with 1 ms jitter cut at 2.25 ms: two consecutive stamps can be 0.5 ms or 9.5 ms
// apart, so indices counted from stamp differences slip; the phase-based indices must not.
TEST(StampGrid, NoIndexSlipWhenJitterNearsHalfAPeriod) {
  const auto truth = trueGrid(12000, 0.005, 0.0, 0);
  const StampGrid g = fitStampGrid(jittered(truth, 1e-3, 0.005, 11));
  ASSERT_TRUE(g.applied) << g.reason;
  EXPECT_EQ(g.missing_samples, 0u);
  EXPECT_LT(errors(g.stamps, truth).max, 0.5e-3);
}

TEST(StampGrid, LeavesArrivalTimesOfABurstyStreamAlone) {
  std::mt19937_64 rng(3);
  std::exponential_distribution<double> gap(10.0);
  std::vector<double> t{0.0};
  for (int i = 0; i < 500; ++i) t.push_back(t.back() + 0.01 + gap(rng));
  const StampGrid g = fitStampGrid(t);
  EXPECT_FALSE(g.applied);
  EXPECT_EQ(g.stamps, t);
}

TEST(DatasetStamps, MovesScansAndKeepsCleanStreams) {
  Dataset d;
  const auto truth = trueGrid(300, 0.1, 0.0, 0);
  const auto t = jittered(truth, 2e-3, 0.1, 5);
  for (double x : t) {
    ScanRecord r;
    r.scan.stamp_s = x;
    d.scans.push_back(r);
  }
  for (double x : trueGrid(3000, 0.01, 0.0, 0)) d.encoders.push_back({x, 0, 0});
  const auto streams = regularizeStamps(d);
  ASSERT_EQ(streams.size(), 2u);
  EXPECT_EQ(streams[0].stream, "encoders");
  EXPECT_FALSE(streams[0].applied);
  EXPECT_EQ(streams[1].stream, "scans");
  EXPECT_TRUE(streams[1].applied);
  EXPECT_TRUE(anyApplied(streams));
  EXPECT_LT(std::abs(d.scans[150].scan.stamp_s - truth[150]), 0.5e-3);
}

// fr079: a 4.7 Hz laser with 3 ms of jitter beside irregular odometry lines. Putting only the
// scans on their grid would shift them against the odometry, so both keep their stamps.
TEST(DatasetStamps, AStreamWithoutAGridKeepsEveryStreamAsLogged) {
  Dataset d;
  const auto truth = trueGrid(300, 0.2, 0.0, 0);
  for (double x : jittered(truth, 3e-3, 0.2, 9)) {
    ScanRecord r;
    r.scan.stamp_s = x;
    d.scans.push_back(r);
  }
  std::mt19937_64 rng(4);
  std::exponential_distribution<double> gap(20.0);
  for (double t = 0.0; t < 61.0; t += 0.01 + gap(rng)) d.odom_nominal.push_back(t, SE2());
  const Dataset before = d;
  const auto streams = regularizeStamps(d);
  EXPECT_FALSE(anyApplied(streams));
  EXPECT_EQ(streams.back().stream, "scans");
  EXPECT_NE(streams.back().reason.find("kept with the other streams"), std::string::npos);
  for (std::size_t k = 0; k < d.scans.size(); ++k)
    EXPECT_EQ(d.scans[k].scan.stamp_s, before.scans[k].scan.stamp_s);
}

}  // namespace
// An RPLIDAR driver stamps its scans 0.1231 and 0.1350 s apart in turn, now and then 0.1350 twice
// (a TurtleBot4's recording): the period is the mean step, 0.1296 s, not the median, 0.1350; a
// missing scan does not change it; without a grid (steps uniform in 0.05-0.15 s) the median
// step. (Where the shorter step is the median, the grid fit takes that step for the period, with
// samples missing throughout, as the median would.)
TEST(StreamPeriod, AlternatingStepsGiveTheirMeanNotTheMedian) {
  std::vector<double> t = {0.0};
  double sum = 0.0;
  for (int k = 1; k < 400; ++k) {
    const double step = (k % 2 || k % 16 == 0) ? 0.1350 : 0.1231;
    t.push_back(t.back() + step);
    sum += step;
  }
  const double mean = sum / 399.0;
  EXPECT_NEAR(streamPeriod(t), mean, 1e-4);
  EXPECT_GT(std::abs(streamPeriod(t) - 0.1350), 0.004);
  std::vector<double> gap = t;
  gap.erase(gap.begin() + 200);
  EXPECT_NEAR(streamPeriod(gap), mean, 1e-4);
  std::vector<double> random = {0.0};
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> step(0.05, 0.15);
  for (int k = 1; k < 400; ++k) random.push_back(random.back() + step(rng));
  std::vector<double> steps;
  for (std::size_t k = 1; k < random.size(); ++k) steps.push_back(random[k] - random[k - 1]);
  std::nth_element(steps.begin(), steps.begin() + steps.size() / 2, steps.end());
  EXPECT_FALSE(fitStampGrid(random).applied);
  EXPECT_NEAR(streamPeriod(random), steps[steps.size() / 2], 0.005);
}

}  // namespace slamprep::algo
