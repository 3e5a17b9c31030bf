#pragma once
// The held_robot fault (docs/faults.md): in some windows of the run the robot's body is held
// still, lifted or pinned against an obstacle, while its wheels keep turning as commanded. The
// encoders then count motion that the gyro, the scans and the ground truth do not see.

#include <nlohmann/json.hpp>
#include <vector>

#include "slamprep/core/se2.hpp"
#include "slamprep/sim/drive/controller.hpp"
#include "slamprep/sim/drive/fault_windows.hpp"
#include "slamprep/sim/drive/faults.hpp"

namespace slamprep::sim {

/// When the body is held: windows drawn before the run from the fault's own stream, so the path
/// check, the motion and the record all see the same ones.
class HeldSchedule {
 public:
  HeldSchedule() = default;  ///< never held (the fault is off)
  /// The windows of faults.held_robot_* on [0, duration_s).
  HeldSchedule(const FaultsConfig& faults, std::uint64_t seed, double duration_s);

  bool heldAt(double t_s) const;
  /// Body motion over [t0_s, t1_s] in kinematic motion: the exact arc of `geometry` for the
  /// commanded wheel turns of each part outside the windows, composed; none inside them.
  SE2 bodyIncrement(const Controller& controller, const DiffDriveParams& geometry, double t0_s,
                    double t1_s) const;
  /// dataset.json's "faults"."held_robot" (docs/faults.md).
  nlohmann::json record(const FaultsConfig& faults) const;
  const std::vector<TimeWindow>& windows() const { return windows_; }

 private:
  std::vector<TimeWindow> windows_;
};

}  // namespace slamprep::sim
