#pragma once
// Drives de-skew over a log's scans in order, keeping what the stateful methods need from the
// previous scan (const-velocity also estimates every scan-to-scan motion for the next one).

#include "slamprep/algo/deskew/deskew.hpp"

namespace slamprep::algo {

class DeskewSequence {
 public:
  /// `inputs.previous` is ignored: the sequence supplies its own.
  DeskewSequence(DeskewMethod method, DeskewInputs inputs, DeskewParams params);

  /// De-skews the next scan. When a scan is refused the chain restarts at the next one (stateful
  /// methods lose their history). `result.match`, when set, is T_prevfirst_curfirst: previous
  /// first-beam lidar frame <- this.
  DeskewResult next(const LaserScan& scan);

  /// Forgets the previous scan (e.g. after a gap in the log).
  void reset() { inputs_.previous.reset(); }

 private:
  DeskewMethod method_;
  DeskewInputs inputs_;
  DeskewParams params_;
};

}  // namespace slamprep::algo
