#include "slamprep/eval/pipeline/match_run.hpp"

#include <cmath>
#include <nlohmann/json.hpp>
#include <numbers>

namespace slamprep::eval {

ScanMatchError scanMatchError(const std::vector<algo::ScanMatch>& matches,
                              const PoseSeries& T_world_lidar_true) {
  ScanMatchError out;
  out.pairs = matches.size();
  for (const algo::ScanMatch& m : matches) out.converged += m.match.converged ? 1 : 0;
  // Each converged match is one step of a chain; the step as the chain holds it is what the
  // calibration intervals are cut from (T_ref_cur up to rounding).
  std::vector<double> trans_m, rot_deg;
  for (const PoseSeries& chain : algo::chainMatches(matches).chains)
    for (std::size_t k = 1; k < chain.size(); ++k) {
      const auto a = T_world_lidar_true.at(chain[k - 1].stamp_s);
      const auto b = T_world_lidar_true.at(chain[k].stamp_s);
      if (!a || !b) continue;
      const SE2 err = between(between(*a, *b), between(chain[k - 1].value, chain[k].value));
      trans_m.push_back(err.translation().norm());
      rot_deg.push_back(std::abs(err.yaw) * 180.0 / std::numbers::pi);
    }
  out.compared = trans_m.size();
  out.translation_m = summarize(std::move(trans_m));
  out.rotation_deg = summarize(std::move(rot_deg));
  return out;
}

MatchRun matchDataset(const Dataset& dataset, const algo::ScanMotionParams& params) {
  MatchRun run;
  run.matches = algo::matchConsecutiveScans(dataset, params);
  run.error = scanMatchError(run.matches,
                             algo::lidarPosesFromGroundTruth(dataset, params.stamp_is_last_beam));
  return run;
}

nlohmann::ordered_json matchLine(double stamp_ref_s, double stamp_cur_s, const algo::IcpResult& m) {
  nlohmann::ordered_json cov = nlohmann::ordered_json::array();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) cov.push_back(m.covariance(r, c));
  return {{"stamp_ref", stamp_ref_s},
          {"stamp_cur", stamp_cur_s},
          {"T_ref_cur", {m.T_ref_cur.x, m.T_ref_cur.y, m.T_ref_cur.yaw}},
          {"converged", m.converged},
          {"iterations", m.iterations},
          {"inliers", m.inliers},
          {"rms_m", m.rms_residual_m},
          {"covariance", cov},
          {"reason", m.reason}};
}

std::string formatMatches(const std::vector<algo::ScanMatch>& matches) {
  std::string text;
  for (const algo::ScanMatch& s : matches)
    text += matchLine(s.stamp_ref_s, s.stamp_cur_s, s.match).dump() + "\n";
  return text;
}

}  // namespace slamprep::eval
