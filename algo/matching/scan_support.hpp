#pragma once
// How well a map explains a scan at a pose (docs/matching.md "Scan support"): what a match is
// accepted on and what picks the best of several matches, independent of where a match started.
//
// Each scan point p, placed by T_ref_cur, is compared with its nearest map point q: the residual
// is the distance to the line fitted at q (point-to-line), or |T p - q| where q has no line. The
// score is the truncated quadratic cost (a robust least-squares cost that outliers cannot
// dominate):
//   cost = 1/n sum_i min(r_i^2, c^2),      c = inlier_distance_m,                     (Eq. 1)
// and the support is the fraction of the *overlapping* points (those with a map point within
// overlap_distance = 5c) that are inliers (r_i < c): a scan turning into a part of the world the
// map has not seen yet says nothing for or against a pose there. A scan with no points costs c^2.

#include <cstddef>

#include "slamprep/algo/matching/icp.hpp"

namespace slamprep::algo {

struct ScanSupport {
  std::size_t points = 0;       ///< scan points scored
  std::size_t overlapping = 0;  ///< of which within 5 inlier_distance_m of a map point
  std::size_t inliers = 0;      ///< of those, closer than inlier_distance_m to the map
  double cost_m2 = 0.0;         ///< Eq. (1)
  double rms_inlier_m = 0.0;    ///< RMS residual of the inliers

  double fraction() const { return overlapping == 0 ? 0.0 : double(inliers) / double(overlapping); }
};

/// Eq. (1) for `cur` (scan points, current frame) placed in `ref`'s frame by T_ref_cur. `ref`
/// must have been built with normals for point-to-line residuals (else point-to-point).
ScanSupport scanSupport(const IcpReference& ref, const Points2& cur, const SE2& T_ref_cur,
                        double inlier_distance_m);

}  // namespace slamprep::algo
