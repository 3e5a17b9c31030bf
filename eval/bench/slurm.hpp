#pragma once
// Scale-out on Slurm: one job array (one suite shard per task) and a merge job that depends on it.
// slamprep writes readable #!/bin/bash job scripts and drives sbatch/scontrol; it schedules
// nothing itself.

#include <filesystem>
#include <string>
#include <vector>

#include "slamprep/eval/bench/suite.hpp"

namespace slamprep::eval {

struct SlurmParams {
  int shards = 4;                        ///< array tasks; trial i runs in task (i mod N) + 1
  std::string partition;                 ///< sbatch --partition; empty: the cluster default
  std::vector<std::string> sbatch_args;  ///< extra sbatch arguments, e.g. "--time=02:00:00"
  int jobs = 0;           ///< worker processes per task; 0: $SLURM_CPUS_PER_TASK (else 1)
  bool plots = true;      ///< the merge job renders the PNG plots
  bool wait = false;      ///< follow the jobs until they end
  double poll_s = 1.0;    ///< seconds between `scontrol show job` polls with `wait`
  std::string suite_arg;  ///< --suite as given: a name under eval/suites/ or a file
  std::filesystem::path results_root = "results";  ///< results/<suite>/ goes below it
};

/// Paths of the generated job scripts and their logs, all below results/<suite>/slurm/.
struct SlurmScripts {
  std::filesystem::path shard_script;  ///< the array job: one shard per task
  std::filesystem::path merge_script;  ///< `slamprep merge` of the suite's results folder
  std::filesystem::path log_dir;
};

struct SlurmResult {
  bool ok = false;                    ///< submitted (and with `wait`: every job completed)
  std::string reason;                 ///< why not, naming the failed shard(s)
  std::vector<int> shards_submitted;  ///< 1-based shard indices in the array
  std::string array_job_id;           ///< empty when every shard was already complete
  std::string merge_job_id;
  std::vector<int> failed_shards;  ///< with `wait`: shards whose task did not complete
  std::string merge_state;         ///< with `wait`: the merge job's final JobState
  SlurmScripts scripts;
};

/// Shards (1-based) of `count` that still lack a complete result under out_dir/shards/K-of-N/
/// made by this very build: those are the ones a (re-)submission must run.
std::vector<int> incompleteShards(const Suite& suite, const std::filesystem::path& out_dir,
                                  int count);

/// Writes the two job scripts into out_dir/slurm/ (absolute paths throughout, so they can be
/// submitted by hand from anywhere).
SlurmScripts writeSlurmScripts(const SlurmParams& params, const std::filesystem::path& out_dir);

/// Submits the missing shards as one array and the dependent merge job (params.wait is not
/// looked at). Throws InputError when sbatch is missing or refuses.
SlurmResult submitToSlurm(const SlurmParams& params);

/// Follows submitted jobs by polling `scontrol show job` every params.poll_s until the array
/// and the merge ended; sets ok, failed_shards, merge_state and a reason naming failed shards.
void waitForSlurm(const SlurmParams& params, SlurmResult& result);

/// The fields of one `scontrol show job` record that `wait` needs.
struct SlurmJobRecord {
  std::string array_task_id;  ///< "3", or a pending range "2-4", or empty for a plain job
  std::string state;          ///< JobState, e.g. PENDING, RUNNING, COMPLETED, FAILED
};

/// Parses `scontrol show job` output (records separated by blank lines).
std::vector<SlurmJobRecord> parseScontrolJobs(const std::string& text);

}  // namespace slamprep::eval
