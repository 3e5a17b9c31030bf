// `slamprep bench`: the main job. Runs a suite, writes results/<suite>/, compares to a baseline.
#include <algorithm>
#include <iostream>
#include <thread>

#include "slamprep/app/choices.hpp"
#include "slamprep/app/commands.hpp"
#include "slamprep/app/common_flags.hpp"
#include "slamprep/app/exit_codes.hpp"
#include "slamprep/app/outputs.hpp"
#include "slamprep/core/error.hpp"
#include "slamprep/core/paths.hpp"
#include "slamprep/core/progress.hpp"
#include "slamprep/eval/bench/bench.hpp"
#include "slamprep/eval/bench/report.hpp"
#include "slamprep/eval/bench/slurm.hpp"
#include "slamprep/eval/bench/trial.hpp"

namespace slamprep::app {
namespace {

struct BenchFlags : CommonFlags {
  eval::BenchOptions options;
  std::string shard;
  std::string compare;
  bool slurm = false;
  eval::SlurmParams slurm_params;
};

// Rendered plots on stdout; kept ones (inputs missing, left as they were) on stderr, so nobody
// takes an old PNG for a fresh one.
void printPlots(const std::filesystem::path& dir, const eval::SuitePlots& plots) {
  for (const auto& name : plots.names)
    if (std::find(plots.kept.begin(), plots.kept.end(), name) != plots.kept.end())
      std::cerr << "plot: trials/ missing: kept plots/" << name << " as it was\n";
    else
      std::cout << "plot: " << (dir / "plots" / name).string() << "\n";
}

void printRegressions(const std::vector<eval::Regression>& regressions) {
  std::cerr << regressions.size() << " metric(s) regressed beyond tolerance:\n";
  for (const auto& r : regressions) {
    if (!r.note.empty())
      std::cerr << "  " << r.metric << ": " << r.note << "\n";
    else
      std::cerr << "  " << r.metric << ": " << r.current << " (baseline " << r.baseline
                << ", tolerance allows " << r.allowed << ")\n";
  }
}

// `--slurm`: submit the shards as a job array plus a dependent merge job instead of running here.
int runOnSlurm(BenchFlags& flags) {
  if (!flags.shard.empty() || flags.options.fresh || !flags.compare.empty() ||
      flags.options.update_baseline)
    throw InputError("--slurm",
                     "cannot be combined with --shard, --fresh, --compare or "
                     "--update-baseline (run them on the merged folder instead)");
  auto& p = flags.slurm_params;
  p.suite_arg = flags.options.suite;
  p.results_root = flags.options.results_root;
  p.jobs = flags.options.jobs;
  p.plots = flags.options.plots;
  auto result = eval::submitToSlurm(p);
  const std::string n = std::to_string(p.shards);
  if (result.array_job_id.empty()) {
    std::cout << "all " << n << " shards already complete; submitted merge job "
              << result.merge_job_id << "\n";
  } else {
    std::cout << "submitted array job " << result.array_job_id << " (shard(s) ";
    for (std::size_t i = 0; i < result.shards_submitted.size(); ++i)
      std::cout << (i ? "," : "") << result.shards_submitted[i];
    std::cout << " of " << n << ") and merge job " << result.merge_job_id
              << " (afterok:" << result.array_job_id << ")\n";
  }
  std::cout << "scripts and logs: " << result.scripts.log_dir.string() << "\n"
            << "follow: squeue -j "
            << (result.array_job_id.empty() ? "" : result.array_job_id + ",") << result.merge_job_id
            << " | sacct -j " << result.merge_job_id << " | scontrol show job "
            << result.merge_job_id << "\n";
  if (!p.wait) return 0;
  std::cout.flush();
  eval::waitForSlurm(p, result);
  if (!result.ok) {
    std::cerr << "slurm run failed: " << result.reason
              << "\nre-run the same command to resubmit only the shards without a result\n";
    return kExitNotDone;
  }
  std::cout << "all shards and the merge completed: "
            << (result.scripts.log_dir.parent_path() / "README.md").string() << "\n";
  return 0;
}

// More workers than 4 per core only add memory and switching (10000 started one per trial);
// with --slurm the count is checked where the tasks run.
void checkJobs(int jobs) {
  const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  if (jobs > 4 * cores)
    throw InputError("--jobs " + std::to_string(jobs),
                     "more than 4 worker processes per core (this machine has " +
                         std::to_string(cores) + "): at most " + std::to_string(4 * cores));
}

int runBenchCommand(BenchFlags& flags) {
  flags.options.progress = !flags.quiet;
  if (flags.slurm) return runOnSlurm(flags);
  checkJobs(flags.options.jobs);
  if (!flags.shard.empty()) flags.options.shard = eval::Shard::parse(flags.shard);
  if (!flags.compare.empty()) checkInputFile(flags.compare, "--compare");  // before any trial
  if (!flags.compare.empty()) flags.options.compare = flags.compare;
  const eval::Suite suite =
      eval::loadSuite(eval::findSuite(flags.options.suite, resolveDataPath("eval/suites")));
  eval::checkSuiteFiles(suite);  // a typo in worlds: is exit 2 now, not every trial failed
  const auto outcome = eval::runBench(flags.options, eval::benchTrial(suite));
  const auto& run = outcome.run;
  std::cerr << "suite " << outcome.suite.name << ": " << run.selected << " trials (" << run.reused
            << " reused, " << run.computed << " computed, " << run.failed.size() << " failed) in "
            << formatDuration(run.seconds) << "\n";
  for (const auto& id : run.failed) std::cerr << "  failed: " << id << "\n";
  if (flags.options.shard) {
    std::cout << "shard " << flags.options.shard->name() << " written to "
              << (outcome.out_dir / "shards" / flags.options.shard->name()).string()
              << "; combine all shards with `slamprep merge " << outcome.out_dir.string() << "`\n";
    return run.failed.empty() ? kExitDone : kExitNotDone;
  }
  std::cout << eval::renderConsoleSummary(outcome.summary)
            << "\nresults: " << (outcome.out_dir / "README.md").string() << "\n";
  printPlots(outcome.out_dir, outcome.plots);
  if (!outcome.regressions.empty()) printRegressions(outcome.regressions);
  if (flags.options.compare && outcome.regressions.empty())
    std::cout << "no regression against " << flags.options.compare->string() << "\n";
  return run.failed.empty() && outcome.complete && outcome.regressions.empty() ? kExitDone
                                                                               : kExitNotDone;
}

}  // namespace

Command addBenchCommand(CLI::App& app) {
  auto flags = std::make_shared<BenchFlags>();
  auto* cli = app.add_subcommand("bench", "Run an experiment suite; write results/<suite>/.");
  cli->footer(
      "Every trial simulates, matches, calibrates, de-skews and measures against the truth;\n"
      "results/<suite>/ gets README.md, summary.json, trials.csv and plots/ (docs/results.md).\n"
      "The results folder is bench's own: an interrupted run resumes in it, --fresh recomputes.\n"
      "bench writes only into a results folder it created (it holds .slamprep-results): an\n"
      "existing folder without that marker is refused (exit 2) and left as it is.\n"
      "Exit 3 when a trial failed, a shard or the merge is incomplete, a metric regressed\n"
      "beyond its tolerance (--compare) or a Slurm job failed (--wait).");
  cli->add_option("--suite", flags->options.suite,
                  "Suite name under eval/suites/ (default, regression, sweep-speed, "
                  "sweep-calibration, calibration-goal, seeds, faults) or a suite YAML file")
      ->capture_default_str();
  cli->add_option("--jobs,-j", flags->options.jobs,
                  "Trials run at once in worker processes (0: one per core); results are the "
                  "same bytes whatever the count; at most 4 per core")
      ->capture_default_str()
      ->check(nonNegative());
  cli->add_option("--shard", flags->shard,
                  "Run only slice K of N (K/N) into results/<suite>/shards/K-of-N/; combine "
                  "with `slamprep merge`");
  cli->add_option("--results", flags->options.results_root, "Folder that holds results/<suite>/")
      ->capture_default_str();
  cli->add_option("--compare", flags->compare,
                  "Baseline summary JSON; exit 3 naming every metric worse than its tolerance "
                  "(tolerances are in the suite file)");
  cli->add_flag("--update-baseline", flags->options.update_baseline,
                "Write this run's summary as results/<suite>/baseline.json");
  cli->add_flag_callback(
      "--no-plots", [flags] { flags->options.plots = false; }, "Skip rendering the PNG plots");
  cli->add_flag("--fresh", flags->options.fresh,
                "Recompute every trial (by default an interrupted run resumes, reusing trials "
                "this same build already finished)");
  addQuiet(cli, *flags);
  cli->add_flag("--slurm", flags->slurm,
                "Submit the suite to Slurm: a job array (one shard per task) and a merge job "
                "that depends on it; shards already complete are not resubmitted");
  cli->add_option("--shards", flags->slurm_params.shards, "Array tasks with --slurm")
      ->capture_default_str()
      ->check(positive());
  cli->add_option("--partition", flags->slurm_params.partition, "sbatch --partition with --slurm");
  cli->add_option(
         "--sbatch-arg", flags->slurm_params.sbatch_args,
         "Extra sbatch argument with --slurm, repeatable (e.g. --sbatch-arg=--time=1:00:00)")
      ->allow_extra_args(false);
  cli->add_flag("--wait", flags->slurm_params.wait,
                "With --slurm: follow the jobs (scontrol show job) and exit 3 naming failed "
                "shards");
  return {cli, [flags] { return runBenchCommand(*flags); }};
}

Command addMergeCommand(CLI::App& app) {
  auto dir = std::make_shared<std::string>();
  auto plots = std::make_shared<bool>(true);
  auto* cli = app.add_subcommand("merge", "Combine the --shard runs of a suite into its results.");
  cli->footer(
      "Reads results/<suite>/shards/*/ and writes the results folder, byte-identical to a\n"
      "single-machine run. Exit 3 while trials are missing. RESULTS_DIR must be a folder bench\n"
      "created (with .slamprep-results); any other is refused (exit 2).");
  cli->add_option("RESULTS_DIR", *dir, "The suite's results folder, e.g. results/default")
      ->required();
  cli->add_flag_callback(
      "--no-plots", [plots] { *plots = false; }, "Skip rendering the PNG plots");
  return {cli, [dir, plots] {
            const auto outcome = eval::mergeShards(*dir, *plots);
            std::cout << eval::renderConsoleSummary(outcome.summary)
                      << "\nresults: " << (outcome.out_dir / "README.md").string() << "\n";
            if (!outcome.complete)
              std::cerr << "incomplete: " << outcome.summary.missing.size()
                        << " trial(s) have no result yet; run the missing shards and merge "
                           "again\n";
            return outcome.complete ? kExitDone : kExitNotDone;
          }};
}

Command addPlotCommand(CLI::App& app) {
  auto dir = std::make_shared<std::string>();
  auto* cli = app.add_subcommand("plot", "Re-render a results folder's plots and README.");
  cli->footer(
      "Renders off-screen (OSMesa) into RESULTS_DIR/plots/ and rewrites its README.md around\n"
      "them; `bench` and `merge` call this themselves. Without trials/ (git ignores it) the\n"
      "first trial's figures cannot be redrawn: their PNGs are kept as they were. RESULTS_DIR\n"
      "must be a folder bench created (with .slamprep-results); any other is refused (exit 2).");
  cli->add_option("RESULTS_DIR", *dir,
                  "A finished results folder with suite.yaml and summary.json, e.g. "
                  "results/default")
      ->required();
  return {cli, [dir] {
            printPlots(*dir, eval::plotResults(*dir));
            std::cout << "report: " << (std::filesystem::path(*dir) / "README.md").string() << "\n";
            return 0;
          }};
}

}  // namespace slamprep::app
