// Calibrates a dataset directory with the installed slamprep libraries: reads it, measures the
// lidar motion by scan matching (scans de-skewed first), cuts one interval per scan match (the
// library's default policy), and estimates r_L, r_R, b and the lidar mount with Censi's joint
// closed form.
//   calibrate_dataset DATASET_DIR
// Prints one `name estimate truth` line per parameter (truth: "-" when the dataset has none).
#include <cstdio>
#include <exception>
#include <slamprep/algo/calibration/joint_censi.hpp>
#include <slamprep/eval/formats/dataset_io.hpp>
#include <slamprep/eval/pipeline/calibration_run.hpp>

namespace {

using namespace slamprep;

int run(const char* dataset_dir) {
  const Dataset dataset = eval::readDataset(dataset_dir);

  const eval::CalibrationMotionOptions options;  // scan matching on de-skewed scans (imu if logged)
  const eval::CalibrationMotion motion = eval::calibrationMotion(dataset, options);

  const algo::JointResult result = algo::calibrateJoint(motion.intervals.intervals);
  if (!result.ok) {
    std::fprintf(stderr, "joint calibration refused: %s\n", result.reason.c_str());
    return 1;
  }
  std::printf("%-13s %d of %zu\n", "intervals", result.intervals_used,
              motion.intervals.intervals.size());

  // Simulated datasets carry the truth: the geometry Bullet used and the mount the lidar had.
  const bool has_truth = dataset.info.true_geometry.has_value();
  const DiffDriveParams g = dataset.info.true_geometry.value_or(DiffDriveParams{});
  const SE2& mount = dataset.info.T_base_lidar;
  auto row = [&](const char* name, double estimate, double truth) {
    if (has_truth)
      std::printf("%-13s %.6f %.6f\n", name, estimate, truth);
    else
      std::printf("%-13s %.6f -\n", name, estimate);
  };
  row("r_L_m", result.geometry.radius_left_m, g.radius_left_m);
  row("r_R_m", result.geometry.radius_right_m, g.radius_right_m);
  row("b_m", result.geometry.wheel_base_m, g.wheel_base_m);
  row("lidar_x_m", result.T_base_lidar.x, mount.x);
  row("lidar_y_m", result.T_base_lidar.y, mount.y);
  row("lidar_yaw_rad", result.T_base_lidar.yaw, mount.yaw);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: calibrate_dataset DATASET_DIR\n");
    return 2;
  }
  try {
    return run(argv[1]);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "calibrate_dataset: %s\n", e.what());
    return 1;
  }
}
