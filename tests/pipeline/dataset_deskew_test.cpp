// deskewDataset: a caller that wants the points only (a matcher) gets the same points without
// the error figures against the truth.
#include "slamprep/eval/pipeline/dataset_deskew.hpp"

#include <gtest/gtest.h>

#include "slamprep/sim/drive/config.hpp"
#include "slamprep/sim/drive/simulator.hpp"

namespace slamprep::eval {
namespace {

TEST(DatasetDeskew, WithoutMeasuringTheSameScansComeOutAndNoErrorFigures) {
  sim::SimConfig c;  // default world and drive, kinematic: truth for every beam
  c.mode = sim::SimMode::kinematic;
  c.duration_s = 8.0;
  const Dataset d = sim::simulate(c).dataset;
  DatasetDeskewOptions options = nominalDeskewOptions(d);
  const DatasetDeskew measured = deskewDataset(d, algo::DeskewMethod::kOdomLinear, options);
  options.measure_errors = false;
  const DatasetDeskew points_only = deskewDataset(d, algo::DeskewMethod::kOdomLinear, options);
  ASSERT_TRUE(measured.error_m);
  EXPECT_GT(measured.error_m->count, 10000u);  // 8 s of 10 Hz scans, hundreds of beams each
  EXPECT_FALSE(points_only.error_m);
  EXPECT_FALSE(points_only.fallback_error_m);
  EXPECT_FALSE(points_only.repacked_error_m);
  EXPECT_EQ(points_only.refused, measured.refused);
  EXPECT_EQ(correctedPoints(points_only), correctedPoints(measured));
}

}  // namespace
}  // namespace slamprep::eval
