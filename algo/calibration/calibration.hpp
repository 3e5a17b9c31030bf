#pragma once
// Odometry calibration (docs/calibration.md): every method, the method registry and the one
// dispatcher, one include.

#include "algo/calibration/calibrate.hpp"
#include "algo/calibration/calibration_method.hpp"
#include "algo/calibration/calibration_result.hpp"
#include "algo/calibration/ceres_refine.hpp"
#include "algo/calibration/direct_linear.hpp"
#include "algo/calibration/interval.hpp"
#include "algo/calibration/joint_censi.hpp"
#include "algo/calibration/model_based.hpp"
#include "algo/calibration/umbmark.hpp"
