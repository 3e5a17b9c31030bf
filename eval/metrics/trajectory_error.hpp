#pragma once
// Trajectory errors with the definitions of the `evo` tool (docs/metrics.md): absolute pose
// error (APE) after an optional rigid SE(2) alignment, and relative pose error (RPE).

#include <string>
#include <vector>

#include "slamprep/core/enum_names.hpp"
#include "slamprep/core/laser_scan.hpp"
#include "slamprep/core/time_series.hpp"
#include "slamprep/eval/metrics/error_stats.hpp"

namespace slamprep::eval {

/// An estimate and the reference at the same stamps.
struct AssociatedPoses {
  std::vector<double> stamps_s;
  std::vector<SE2> estimate;   ///< estimate poses that found a reference
  std::vector<SE2> reference;  ///< reference interpolated (geodesically) at those stamps
  std::size_t unmatched = 0;   ///< estimate poses without a reference close enough in time
};

/// The reference at every estimate stamp t, interpolated between its bracketing samples
/// t_a <= t <= t_b; used only when t equals a reference stamp or max(t - t_a, t_b - t) <=
/// max_time_difference_s (no interpolation across gaps, no extrapolation).
AssociatedPoses associateByTime(const PoseSeries& estimate, const PoseSeries& reference,
                                double max_time_difference_s);

/// Closed-form rigid alignment in 2D (Umeyama/Horn without scale).
struct AlignmentResult {
  bool ok = false;
  std::string reason;
  SE2 T_ref_est;        ///< argmin_T sum |q_i - T p_i|^2
  double rmse_m = 0.0;  ///< sqrt(mean |q_i - T p_i|^2) at the optimum
};

/// Aligns points p (estimate) onto q (reference), corresponding by index. Refuses fewer than two
/// points or all p coincident (rotation unobservable).
AlignmentResult alignRigid2D(const Points2& p_est, const Points2& q_ref);

struct ApeParams {
  bool align = true;                    ///< rigid SE(2) alignment of the positions first (evo -a)
  bool align_origin = false;            ///< else: first estimate pose onto the reference's (evo
                                        ///< --align_origin), the natural frame of dead reckoning
  double max_time_difference_s = 0.01;  ///< association tolerance, see associateByTime
};

struct ApeResult {
  bool ok = false;
  std::string reason;
  std::size_t matched = 0;       ///< poses compared
  std::size_t unmatched = 0;     ///< estimate poses without reference
  SE2 T_ref_est;                 ///< the alignment applied to the estimate (identity if none)
  ErrorStats translation_m;      ///< |t(E_i)|, E_i = Q_i^-1 (T P_i)
  ErrorStats rotation_deg;       ///< |angle(E_i)| in degrees
  std::vector<double> stamps_s;  ///< per compared pose
  std::vector<double> translation_errors_m;  ///< per compared pose
  std::vector<double> rotation_errors_deg;   ///< per compared pose
};

/// APE of `estimate` (P) against `reference` (Q), associated by time.
ApeResult absolutePoseError(const PoseSeries& estimate, const PoseSeries& reference,
                            const ApeParams& params = {});

enum class DeltaUnit { kFrames, kMeters };
/// As `score rpe --unit` and its JSON spell them.
inline constexpr auto kDeltaUnitNames = std::to_array<EnumName<DeltaUnit>>({
    {DeltaUnit::kFrames, "frames"},
    {DeltaUnit::kMeters, "m"},
});

struct RpeParams {
  double delta = 1.0;                   ///< pose-pair spacing, in `unit`
  DeltaUnit unit = DeltaUnit::kFrames;  ///< frames (delta rounded, >= 1) or metres of path
  bool all_pairs = false;               ///< every start index instead of consecutive segments
  double rel_delta_tol = 0.1;           ///< all_pairs in metres: accept |path - delta| <= tol*delta
  bool pairs_from_reference = false;    ///< measure the path on the reference (evo: estimate)
  double max_time_difference_s = 0.01;  ///< association tolerance, see associateByTime
};

struct RpeResult {
  bool ok = false;
  std::string reason;
  std::size_t pairs = 0;
  std::size_t unmatched = 0;  ///< estimate poses without reference
  ErrorStats translation_m;   ///< |t(E_ij)|
  ErrorStats rotation_deg;    ///< |angle(E_ij)| in degrees
  std::vector<std::pair<std::size_t, std::size_t>>
      index_pairs;  ///< (i, j) into the associated poses
  std::vector<double> translation_errors_m;
  std::vector<double> rotation_errors_deg;
};

/// RPE: E_ij = (Q_i^-1 Q_j)^-1 (P_i^-1 P_j) over pairs (i, j) chosen by RpeParams.
RpeResult relativePoseError(const PoseSeries& estimate, const PoseSeries& reference,
                            const RpeParams& params = {});

/// Index pairs of RPE, as evo's id_pairs_from_delta chooses them (exposed for tests), on the
/// poses whose path is measured:
/// - frames: (i, i + d) for i = 0, d, 2d, ...; with all_pairs for every i;
/// - metres: walking the poses, a mark is set each time the path since the previous mark (or
///   since pose 0) reaches delta; pairs are consecutive marks (pose 0 is not a mark);
/// - metres, all_pairs: for every i, the j >= i whose path from i is nearest to delta (ties to
///   the lower j), kept when |path - delta| <= rel_delta_tol * delta.
std::vector<std::pair<std::size_t, std::size_t>> rpePairs(const std::vector<SE2>& poses,
                                                          const RpeParams& params);

}  // namespace slamprep::eval
