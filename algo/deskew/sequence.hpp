#pragma once
// Drives de-skew over a dataset's scans in order, keeping what the stateful methods need from the
// previous scan, and optionally estimating every scan-to-scan motion (what calibration uses).

#include <optional>

#include "algo/deskew/deskew.hpp"

namespace slamprep::algo {

struct DeskewSequenceParams {
  DeskewParams deskew;
  /// Estimate the motion between every pair of consecutive scans (estimateScanMotion) even when
  /// the method does not need it (`slamprep match`); const-velocity always does, vicp and
  /// odom-icp match inside.
  bool match_every_scan = false;
};

class DeskewSequence {
 public:
  DeskewSequence(DeskewMethod method, DeskewSequenceParams params);

  /// De-skews the next scan. `input.previous` is ignored: the sequence supplies its own. When a
  /// scan is refused the chain restarts at the next one (stateful methods lose their history).
  /// `result.match`, when set, is T_prevfirst_curfirst: previous first-beam lidar frame <- this.
  DeskewResult next(DeskewInput input);

  /// Forgets the previous scan (e.g. after a gap in the log).
  void reset() { previous_.reset(); }

 private:
  DeskewMethod method_;
  DeskewSequenceParams params_;
  std::optional<PreviousScan> previous_;
};

}  // namespace slamprep::algo
