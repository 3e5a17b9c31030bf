// `slamprep match`: scan-to-scan lidar motions of a dataset (point-to-line ICP), written as
// matches.jsonl (docs/deskew.md), with their error against ground truth when there is truth.
#include <filesystem>
#include <iomanip>
#include <iostream>

#include "app/commands.hpp"
#include "core/atomic_file.hpp"
#include "eval/bench/match_run.hpp"
#include "eval/formats/dataset_io.hpp"

namespace slamprep::app {
namespace {

struct MatchFlags {
  std::string dataset;
  std::string out;  // default DATASET/matches.jsonl
  std::string deskew = "vicp";
  bool stamp_is_last_beam = false;
};

int runMatch(const MatchFlags& flags) {
  const Dataset d = eval::readDataset(flags.dataset);
  algo::ScanMotionParams params;  // a lidar-only log: no odometry guess
  params.matcher = flags.deskew == "vicp" ? algo::ScanMatcher::kVicp : algo::ScanMatcher::kIcp;
  params.guess = algo::MotionGuess::kConstantVelocity;
  params.stamp_is_last_beam = flags.stamp_is_last_beam;
  const eval::MatchRun run = eval::matchDataset(d, params);
  const std::filesystem::path out = flags.out.empty()
                                        ? std::filesystem::path(flags.dataset) / "matches.jsonl"
                                        : std::filesystem::path(flags.out);
  writeFileAtomic(out, eval::formatMatches(run.matches));
  const eval::ScanMatchError& e = run.error;
  std::cout << "matched " << e.pairs << " consecutive scan pairs (" << flags.deskew
            << "), converged " << e.converged << "\n";
  if (e.compared > 0)
    std::cout << std::fixed << std::setprecision(3)
              << "mean error vs ground truth: " << 1e3 * e.translation_m.mean << " mm, "
              << e.rotation_deg.mean << " deg\n";
  std::cout << "wrote " << out.string() << "\n";
  return e.converged == e.pairs ? 0 : 3;
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
