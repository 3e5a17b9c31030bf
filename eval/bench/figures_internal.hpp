#pragma once
// The suite figures, one function each (figures.cpp decides which a suite gets).

#include <optional>
#include <vector>

#include "slamprep/eval/bench/artifacts_record.hpp"
#include "slamprep/eval/bench/figure_groups.hpp"
#include "slamprep/eval/bench/suite.hpp"
#include "slamprep/eval/plot/plot.hpp"

namespace slamprep::eval {

// figures_calibration.cpp
/// Error of every method and parameter, one row of panels per group. When every group has at
/// least kMinSeedsForBoxes seeds in `trials_by_group` (one entry per group, its rows of
/// trials.csv): box plots of the signed error on linear axes, boxes far off the others' scale on
/// a panel of their own. Else dots of the mean absolute error with min..max whiskers on log axes.
plot::Figure calibrationFigure(const std::vector<SummaryGroup>& groups,
                               const std::vector<TrialRows>& trials_by_group = {});
/// Error against driving time (the duration_s sweep axis), one column per other sweep value.
plot::Figure calibrationVsTimeFigure(const std::vector<SummaryGroup>& groups);

// figures_deskew.cpp
/// Mean point error of every method, one panel per group, dots with min..max whiskers over its
/// seeds.
plot::Figure deskewFigure(const std::vector<SummaryGroup>& groups);
/// Mean point error against the measured speed of a scenario series, one panel per other sweep
/// value; nullopt when the scenarios are not a series (scenarioSeries).
std::optional<plot::Figure> deskewVsSpeedFigure(const std::vector<SummaryGroup>& groups);

// figures_maps.cpp
plot::Figure trajectoryFigure(const Suite& suite, const TrajectoriesRecord& trajectory);
plot::Figure scanFigure(const Suite& suite, const ArtifactScanRecord& scan);
/// Dead-reckoning error over time, nominal and calibrated geometry (evo's APE plot).
plot::Figure odometryErrorFigure(const OdometryErrorRecord& odometry_error);

}  // namespace slamprep::eval
