// `slamprep match`: scan-to-scan lidar motions of a dataset (point-to-line ICP), written as
// matches.jsonl (docs/deskew.md), with their error against ground truth when there is truth.
#include <filesystem>
#include <iomanip>
#include <iostream>

#include "app/choices.hpp"
#include "app/commands.hpp"
#include "app/exit_codes.hpp"
#include "app/outputs.hpp"
#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "eval/bench/command_progress.hpp"
#include "eval/bench/match_run.hpp"
#include "eval/formats/dataset_io.hpp"

namespace slamprep::app {
namespace {

struct MatchFlags {
  std::string dataset;
  std::string out;  // nothing is written without it
  std::string deskew = "vicp";
  bool stamp_is_last_beam = false;
  bool strict = false;
  bool force = false;
};

int runMatch(const MatchFlags& flags) {
  checkInputDataset(flags.dataset, "DATASET");
  if (!flags.out.empty()) {
    checkNotInside(flags.out, flags.dataset, "--out");
    checkOutputFile(flags.out, "--out", flags.force);
  }
  const Dataset d = eval::readDataset(flags.dataset);
  if (d.scans.size() < 2) throw InputError(flags.dataset, "needs at least two scans to match");
  algo::ScanMotionParams params;  // a lidar-only log: no odometry guess
  params.matcher = flags.deskew == "vicp" ? algo::ScanMatcher::kVicp : algo::ScanMatcher::kIcp;
  params.guess = algo::MotionGuess::kConstantVelocity;
  params.stamp_is_last_beam = flags.stamp_is_last_beam;
  const eval::MatchRun run = [&] {
    eval::CommandProgress progress(1, "runs", "match");
    eval::StageReporter stages(flags.dataset, 1);
    stages.begin("match");
    return eval::matchDataset(d, params);
  }();
  if (!flags.out.empty()) writeFileAtomic(flags.out, eval::formatMatches(run.matches));
  const eval::ScanMatchError& e = run.error;
  std::cout << "matched " << e.pairs << " consecutive scan pairs (" << flags.deskew
            << "), converged " << e.converged << "\n";
  if (e.compared > 0)
    std::cout << std::fixed << std::setprecision(3)
              << "mean error vs ground truth: " << 1e3 * e.translation_m.mean << " mm, "
              << e.rotation_deg.mean << " deg\n";
  std::cout << (flags.out.empty() ? "no --out: no matches written" : "wrote " + flags.out) << "\n";
  return refusalExitCode(e.converged == 0, e.converged < e.pairs, flags.strict);
}

}  // namespace

Command addMatchCommand(CLI::App& app) {
  auto flags = std::make_shared<MatchFlags>();
  auto* cli =
      app.add_subcommand("match", "Scan-to-scan lidar motions of a dataset (point-to-line ICP).");
  cli->footer(
      "Matches every consecutive scan pair; prints the error against ground truth when there is\n"
      "one; --out FILE writes one JSON line per pair (docs/deskew.md). Exit 3 when no pair\n"
      "converged, or with --strict when any did not.");
  cli->add_option("DATASET", flags->dataset, "dataset directory (read only)")->required();
  cli->add_option("--out", flags->out, "write the matches to FILE (without it nothing is written)");
  cli->add_flag("--force", flags->force,
                "replace an existing --out; the old one stays until the new is complete");
  cli->add_flag("--strict", flags->strict, "exit 3 when any pair did not converge, not only all");
  cli->add_option("--deskew", flags->deskew,
                  "vicp: de-skew both scans with the velocity estimated jointly with the match; "
                  "none: match the scans as measured")
      ->check(oneOf("de-skew", {"vicp", "none"}))
      ->capture_default_str();
  cli->add_flag("--stamp-is-last-beam", flags->stamp_is_last_beam,
                "the scans' stamps mark their last beam, not their first");
  return {cli, [flags] { return runMatch(*flags); }};
}

}  // namespace slamprep::app
