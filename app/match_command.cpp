// `slamprep match`: scan-to-scan lidar motions of a dataset (point-to-line ICP), written as
// matches.jsonl (docs/deskew.md), with their error against ground truth when there is truth.
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>
#include <numbers>

#include "algo/deskew/deskew.hpp"
#include "algo/matching/icp.hpp"
#include "app/commands.hpp"
#include "core/atomic_file.hpp"
#include "core/dataset.hpp"
#include "core/error.hpp"
#include "eval/formats/dataset_io.hpp"

namespace slamprep::app {
namespace {

struct MatchFlags {
  std::string dataset;
  std::string out;  // default DATASET/matches.jsonl
  std::string deskew = "vicp";
  bool stamp_is_last_beam = false;
};

nlohmann::ordered_json line(double stamp_ref, double stamp_cur, const algo::IcpResult& m) {
  nlohmann::ordered_json cov = nlohmann::ordered_json::array();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) cov.push_back(m.covariance(r, c));
  return {{"stamp_ref", stamp_ref},
          {"stamp_cur", stamp_cur},
          {"T_ref_cur", {m.T_ref_cur.x, m.T_ref_cur.y, m.T_ref_cur.yaw}},
          {"converged", m.converged},
          {"iterations", m.iterations},
          {"inliers", m.inliers},
          {"rms_m", m.rms_residual_m},
          {"covariance", cov},
          {"reason", m.reason}};
}

int runMatch(const MatchFlags& flags) {
  const Dataset d = eval::readDataset(flags.dataset);
  const bool vicp = flags.deskew == "vicp";
  algo::DeskewParams params;
  std::string text;
  std::size_t converged = 0, pairs = 0;
  double sum_t_err = 0.0, sum_yaw_err = 0.0;
  std::size_t truth_pairs = 0;
  Eigen::Vector3d twist = Eigen::Vector3d::Zero();  // last motion: the next guess
  for (std::size_t k = 1; k < d.scans.size(); ++k) {
    const LaserScan& prev = d.scans[k - 1].scan;
    const LaserScan& cur = d.scans[k].scan;
    const double t0 = algo::firstBeamTime(prev, flags.stamp_is_last_beam);
    const double t1 = algo::firstBeamTime(cur, flags.stamp_is_last_beam);
    if (!(t1 > t0)) throw InputError(flags.dataset + "/scans.jsonl", "scan stamps not increasing");
    algo::IcpResult m;
    if (vicp) {
      algo::PreviousScan p{prev, flags.stamp_is_last_beam, std::nullopt, std::nullopt};
      const algo::MotionEstimate e =
          algo::estimateScanMotion(p, cur, flags.stamp_is_last_beam, twist, params);
      m = e.match;
      if (!e.ok) m.reason = e.reason.empty() ? "no match" : e.reason;
      if (e.ok) twist = e.twist_lidar;
    } else {
      m = algo::matchPointToLine(prev.points(), cur.points(), SE2::exp(twist * (t1 - t0)),
                                 params.icp);
      if (m.converged) twist = m.T_ref_cur.log() / (t1 - t0);
    }
    ++pairs;
    text += line(t0, t1, m).dump() + "\n";
    if (!m.converged) continue;
    ++converged;
    const auto T0 = d.groundtruth.at(t0), T1 = d.groundtruth.at(t1);
    if (T0 && T1) {
      const SE2 err =
          between(between(*T0 * d.info.T_base_lidar, *T1 * d.info.T_base_lidar), m.T_ref_cur);
      sum_t_err += err.translation().norm();
      sum_yaw_err += std::abs(err.yaw);
      ++truth_pairs;
    }
  }
  const std::filesystem::path out = flags.out.empty()
                                        ? std::filesystem::path(flags.dataset) / "matches.jsonl"
                                        : std::filesystem::path(flags.out);
  writeFileAtomic(out, text);
  std::cout << "matched " << pairs << " consecutive scan pairs (" << flags.deskew << "), converged "
            << converged << "\n";
  if (truth_pairs > 0)
    std::cout << std::fixed << std::setprecision(3)
              << "mean error vs ground truth: " << 1e3 * sum_t_err / truth_pairs << " mm, "
              << sum_yaw_err / truth_pairs * 180.0 / std::numbers::pi << " deg\n";
  std::cout << "wrote " << out.string() << "\n";
  return converged == pairs ? 0 : 3;
}

}  // namespace

Command addMatchCommand(CLI::App& app) {
  auto flags = std::make_shared<MatchFlags>();
  auto* cli = app.add_subcommand(
      "match", "Scan-to-scan lidar motions (point-to-line ICP) of a dataset -> matches.jsonl.");
  cli->add_option("DATASET", flags->dataset, "dataset directory")->required();
  cli->add_option("--out", flags->out, "output file (default DATASET/matches.jsonl)");
  cli->add_option("--deskew", flags->deskew,
                  "vicp: de-skew both scans with the velocity estimated jointly with the match; "
                  "none: match the scans as measured")
      ->check(CLI::IsMember({"vicp", "none"}))
      ->capture_default_str();
  cli->add_flag("--stamp-is-last-beam", flags->stamp_is_last_beam,
                "the scans' stamps mark their last beam, not their first");
  return {cli, [flags] { return runMatch(*flags); }};
}

}  // namespace slamprep::app
