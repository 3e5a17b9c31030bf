#pragma once
// Odometry calibration (docs/calibration.md): every method, the method registry and the one
// dispatcher, one include.

#include "slamprep/algo/calibration/calibrate.hpp"
#include "slamprep/algo/calibration/calibration_method.hpp"
#include "slamprep/algo/calibration/calibration_result.hpp"
#include "slamprep/algo/calibration/ceres_refine.hpp"
#include "slamprep/algo/calibration/direct_linear.hpp"
#include "slamprep/algo/calibration/interval.hpp"
#include "slamprep/algo/calibration/joint_censi.hpp"
#include "slamprep/algo/calibration/model_based.hpp"
#include "slamprep/algo/calibration/umbmark.hpp"
