// Writes the sample figures to <build>/plots/ (to look at) and checks they read back.

#include "sample_figures.hpp"

#include <gtest/gtest.h>

#include "slamprep/eval/plot/plot.hpp"

namespace slamprep::eval::plot {
namespace {

std::filesystem::path outputDir() {
  const std::filesystem::path dir = std::filesystem::path(SLAMPREP_BINARY_DIR) / "plots";
  std::filesystem::create_directories(dir);
  return dir;
}

void writeAndCheck(const Figure& figure, const std::string& name) {
  const auto path = outputDir() / name;
  renderPng(figure, path);
  const Image back = readPng(path);
  EXPECT_EQ(back.width, figure.width_px);
  EXPECT_EQ(back.height, figure.height_px);
}

TEST(SampleFigures, SinglePanels) {
  writeAndCheck({.axes = {samples::deskewAxes()}}, "deskew_error.png");
  writeAndCheck({.axes = {samples::calibrationAxes(Style::Bars)}}, "calibration_bars.png");
  writeAndCheck({.axes = {samples::calibrationAxes(Style::Markers)}}, "calibration_markers.png");
  writeAndCheck({.axes = {samples::calibrationBoxAxes()}}, "calibration_boxes.png");
  writeAndCheck({.axes = {samples::trajectoryAxes()}}, "trajectories.png");
  writeAndCheck({.axes = {samples::scanAxes()}}, "scan.png");
  writeAndCheck({.axes = {samples::errorVsTimeAxes()}}, "error_vs_time.png");
}

TEST(SampleFigures, PanelGrid) {
  Figure figure{.width_px = 1600,
                .height_px = 1200,
                .title = "slamprep bench: sample report",
                .rows = 2,
                .cols = 2};
  figure.axes = {samples::deskewAxes(), samples::calibrationAxes(Style::Bars),
                 samples::trajectoryAxes(), samples::scanAxes()};
  writeAndCheck(figure, "panels.png");
}

}  // namespace
}  // namespace slamprep::eval::plot
