#include "slamprep/eval/bench/slurm.hpp"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string_view>
#include <thread>

#include "slamprep/core/atomic_file.hpp"
#include "slamprep/core/error.hpp"
#include "slamprep/core/paths.hpp"
#include "slamprep/core/shell_quote.hpp"
#include "slamprep/eval/bench/bench.hpp"
#include "slamprep/eval/bench/results_folder.hpp"
#include "slamprep/eval/bench/runner.hpp"

extern char** environ;

namespace slamprep::eval {
namespace {

namespace fs = std::filesystem;

struct ProcessOutput {
  int exit_code = -1;
  std::string output;  ///< stdout and stderr together
};

// Runs argv[0] from PATH with the arguments passed as they are (no shell), capturing output.
ProcessOutput runProcess(const std::vector<std::string>& argv) {
  int fds[2];
  if (::pipe(fds) != 0) throw std::runtime_error("pipe failed");
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, fds[1], STDOUT_FILENO);
  posix_spawn_file_actions_adddup2(&actions, fds[1], STDERR_FILENO);
  posix_spawn_file_actions_addclose(&actions, fds[0]);
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  pid_t pid = 0;
  const int err = ::posix_spawnp(&pid, args[0], &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  ::close(fds[1]);
  if (err != 0) {
    ::close(fds[0]);
    throw InputError(argv[0], std::string("cannot run (") + std::strerror(err) +
                                  "): install the Slurm client (slurm-client) or run on a "
                                  "cluster login node");
  }
  ProcessOutput out;
  char buf[4096];
  ssize_t n = 0;
  while ((n = ::read(fds[0], buf, sizeof buf)) > 0 || (n < 0 && errno == EINTR))
    if (n > 0) out.output.append(buf, static_cast<std::size_t>(n));
  ::close(fds[0]);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  // posix_spawnp reports a missing program as exit 127 from the child on some libcs.
  out.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  if (out.exit_code == 127)
    throw InputError(argv[0],
                     "not found on PATH: install the Slurm client (slurm-client) or run "
                     "on a cluster login node");
  return out;
}

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  const auto e = s.find_last_not_of(" \t\r\n");
  return b == std::string::npos ? "" : s.substr(b, e - b + 1);
}

std::string joinShards(const std::vector<int>& shards) {
  std::string s;
  for (int k : shards) {
    if (!s.empty()) s.push_back(',');
    s.append(std::to_string(k));
  }
  return s;
}

// `sbatch --parsable` prints "<id>" or "<id>;<cluster>".
std::string submit(std::vector<std::string> argv, const SlurmParams& params,
                   const fs::path& script) {
  if (!params.partition.empty()) argv.push_back("--partition=" + params.partition);
  argv.insert(argv.end(), params.sbatch_args.begin(), params.sbatch_args.end());
  argv.push_back(script.string());
  const auto out = runProcess(argv);
  const std::string id = trim(out.output.substr(0, out.output.find(';')));
  if (out.exit_code != 0 || id.empty() || id.find_first_not_of("0123456789") != std::string::npos)
    throw InputError("sbatch " + script.string(), "submission failed: " + trim(out.output));
  return id;
}

bool terminalState(const std::string& state) {
  return !state.empty() && state != "PENDING" && state != "RUNNING" && state != "CONFIGURING" &&
         state != "COMPLETING" && state != "REQUEUED" && state != "RESIZING" &&
         state != "SUSPENDED" && state != "STAGE_OUT" && state != "SIGNALING";
}

// Polls `scontrol show job <id>`; returns its records, empty once slurmctld forgot the job.
std::vector<SlurmJobRecord> showJob(const std::string& id) {
  const auto out = runProcess({"scontrol", "show", "job", id});
  if (out.exit_code != 0) {
    if (out.output.find("Invalid job id") != std::string::npos) return {};
    throw InputError("scontrol show job " + id, trim(out.output));
  }
  return parseScontrolJobs(out.output);
}

bool pollOnce(SlurmResult& result, std::map<int, std::string>& ended, std::string& last_line);

// Follows the array and the merge until both ended; fills failed_shards and merge_state.
void waitForJobs(const SlurmParams& params, SlurmResult& result) {
  const auto poll = std::chrono::duration<double>(std::max(0.05, params.poll_s));
  std::string last_line;
  int scontrol_errors = 0;
  std::map<int, std::string> ended;  // shard -> terminal JobState
  while (true) {
    try {
      if (pollOnce(result, ended, last_line)) return;
      scontrol_errors = 0;
    } catch (const InputError& e) {
      // slurmctld may be briefly unreachable (restart, failover): give up after ~30 polls.
      if (++scontrol_errors > 30) throw;
      std::cerr << "slurm: " << e.what() << " (retrying)\n";
    }
    std::this_thread::sleep_for(poll);
  }
}

// One poll of the array and the merge; true once both ended (results stored in `result`).
bool pollOnce(SlurmResult& result, std::map<int, std::string>& ended, std::string& last_line) {
  // Task states are remembered once terminal: slurmctld forgets finished records after
  // MinJobAge (300 s by default) while later tasks may still run.
  bool array_known = false;
  if (!result.array_job_id.empty())
    for (const auto& r : showJob(result.array_job_id)) {
      array_known = true;
      const bool single = !r.array_task_id.empty() &&
                          r.array_task_id.find_first_not_of("0123456789") == std::string::npos;
      if (single && terminalState(r.state)) ended.emplace(std::stoi(r.array_task_id), r.state);
    }
  // A forgotten array with tasks never seen ending: their state is unknown (not COMPLETED).
  if (!array_known)
    for (int k : result.shards_submitted) ended.emplace(k, "UNKNOWN");
  const bool array_done = ended.size() >= result.shards_submitted.size();
  const auto merge = showJob(result.merge_job_id);
  const std::string merge_state = merge.empty() ? "UNKNOWN" : merge.front().state;
  const std::string line = "slurm: " + std::to_string(ended.size()) + "/" +
                           std::to_string(result.shards_submitted.size()) +
                           " shard task(s) ended, merge " + merge_state;
  if (line != last_line) std::cerr << line << "\n";
  last_line = line;
  if (!array_done || !terminalState(merge_state)) return false;
  result.failed_shards.clear();
  for (const auto& [k, state] : ended)
    if (state != "COMPLETED") result.failed_shards.push_back(k);
  result.merge_state = merge_state;
  return true;
}

bool isControl(char c) {
  return static_cast<unsigned char>(c) < 0x20 || c == 0x7f;
}

// The text with its control characters shown as \xNN, for a message.
std::string printable(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (!isControl(c)) {
      out += c;
      continue;
    }
    char hex[8];
    std::snprintf(hex, sizeof hex, "\\x%02x", static_cast<unsigned char>(c));
    out += hex;
  }
  return out;
}

// A newline in a name or path would end a comment or an #SBATCH line and start a command, and no
// quoting survives both bash and sbatch's directive parser: such text is refused.
void refuseControlCharacters(const std::string& text, const std::string& what) {
  if (std::any_of(text.begin(), text.end(), isControl))
    throw InputError(what + " '" + printable(text) + "'",
                     "holds a control character (newline, tab, ...): it cannot go into a Slurm "
                     "job script");
}

// One word of an #SBATCH line. sbatch ends a word at a blank outside quotes (a backslash does not
// protect it), and at an unquoted '#'; inside double quotes a backslash takes the next character
// as it is. So: double quotes, and a backslash before '"', '\\', '\'' and '#' (older parsers
// end a word at '#' even inside quotes).
std::string sbatchWord(const std::string& word) {
  std::string out = "\"";
  for (char c : word) {
    if (std::string_view("\"\\'#").find(c) != std::string_view::npos) out += '\\';
    out += c;
  }
  return out + '"';
}

// A path for --output: Slurm expands %-patterns (%a, %j) there; "%%" is a literal '%'.
std::string sbatchOutputPath(const std::string& path) {
  std::string out;
  for (char c : path) out += c == '%' ? std::string("%%") : std::string(1, c);
  return sbatchWord(out);
}

std::string shardScript(const SlurmParams& params, const fs::path& out_dir, const fs::path& exe,
                        const fs::path& workdir, const std::string& suite) {
  const std::string n = std::to_string(params.shards);
  const fs::path log_dir = out_dir / "slurm";
  std::ostringstream s;
  s << "#!/bin/bash\n"
    << "# slamprep suite " << shellQuote(out_dir.filename().string())
    << ": one shard per array task.\n"
    << "# Submit by hand: sbatch --array=1-" << n << " "
    << shellQuote((log_dir / "shard.sh").string())
    << "\n# (or --array=K,... for the shards still missing). Task K runs slice K of " << n
    << " into " << (out_dir / "shards").string() << "/K-of-" << n << "/.\n"
    << "#SBATCH --job-name=" << sbatchWord("slamprep-" + out_dir.filename().string()) << "\n"
    << "#SBATCH --output=" << sbatchOutputPath((log_dir / "shard-").string()) << "%a-of-" << n
    << ".log\n"
    << "set -euo pipefail\n"
    << "cd " << shellQuote(workdir.string()) << "\n"
    << "exec " << shellQuote(exe.string()) << " bench --quiet --no-plots \\\n"
    << "  --suite " << shellQuote(suite) << " \\\n"
    << "  --results " << shellQuote(params.results_root.string()) << " \\\n"
    << "  --shard \"${SLURM_ARRAY_TASK_ID}/" << n << "\" \\\n"
    << "  --jobs "
    << (params.jobs > 0 ? std::to_string(params.jobs) : "\"${SLURM_CPUS_PER_TASK:-1}\"") << "\n";
  return s.str();
}

std::string mergeScript(const SlurmParams& params, const fs::path& out_dir, const fs::path& exe,
                        const fs::path& workdir) {
  const fs::path log_dir = out_dir / "slurm";
  std::ostringstream s;
  s << "#!/bin/bash\n"
    << "# slamprep suite " << shellQuote(out_dir.filename().string())
    << ": combine the shards once the array completed.\n"
    << "# Submit by hand: sbatch --dependency=afterok:<array job id> --kill-on-invalid-dep=yes "
    << shellQuote((log_dir / "merge.sh").string()) << "\n"
    << "#SBATCH --job-name=" << sbatchWord("slamprep-" + out_dir.filename().string() + "-merge")
    << "\n"
    << "#SBATCH --output=" << sbatchOutputPath((log_dir / "merge.log").string()) << "\n"
    << "set -euo pipefail\n"
    << "cd " << shellQuote(workdir.string()) << "\n"
    << "exec " << shellQuote(exe.string()) << " merge " << shellQuote(out_dir.string())
    << (params.plots ? "" : " --no-plots") << "\n";
  return s.str();
}

}  // namespace

std::vector<SlurmJobRecord> parseScontrolJobs(const std::string& text) {
  std::vector<SlurmJobRecord> records;
  std::istringstream in(text);
  std::string line;
  SlurmJobRecord current;
  bool open = false;
  auto field = [](const std::string& l, const std::string& key, std::string& value) {
    for (std::size_t at = l.find(key); at != std::string::npos; at = l.find(key, at + 1)) {
      if (at != 0 && l[at - 1] != ' ') continue;  // "ArrayTaskId=" not inside another key
      const auto start = at + key.size();
      value = l.substr(start, l.find(' ', start) - start);
      return;
    }
  };
  while (std::getline(in, line)) {
    if (trim(line).empty()) {
      if (open) records.push_back(current);
      current = {};
      open = false;
      continue;
    }
    const std::string l = std::string(1, ' ').append(trim(line));
    if (l.find(" JobId=") == 0 && open) {
      records.push_back(current);
      current = {};
    }
    open = true;
    field(l, "ArrayTaskId=", current.array_task_id);
    field(l, "JobState=", current.state);
  }
  if (open) records.push_back(current);
  return records;
}

std::vector<int> incompleteShards(const Suite& suite, const fs::path& out_dir, int count) {
  auto trials = expandTrials(suite);
  attachInputDigests(trials);  // as runBench stores them, so complete shards are recognised
  const std::string build = binaryFingerprint();
  std::vector<int> missing;
  for (int k = 1; k <= count; ++k) {
    const Shard shard{k, count};
    const fs::path dir = out_dir / "shards" / shard.name();
    bool complete =
        fs::is_regular_file(dir / ".slamprep-build") && readFile(dir / ".slamprep-build") == build;
    for (const auto& t : trials)
      if (complete && shard.contains(t.index))
        complete = isTrialComplete(dir / "trials" / (t.id + ".json"), t);
    if (!complete) missing.push_back(k);
  }
  return missing;
}

SlurmScripts writeSlurmScripts(const SlurmParams& params, const fs::path& out_dir) {
  const fs::path exe = fs::read_symlink("/proc/self/exe");
  const fs::path workdir = fs::current_path();
  // A suite file is passed by absolute path; a suite name resolves the same way in `workdir`.
  const fs::path suite_path(params.suite_arg);
  const std::string suite = suite_path.has_extension() || suite_path.has_parent_path()
                                ? fs::absolute(suite_path).lexically_normal().string()
                                : params.suite_arg;
  refuseControlCharacters(out_dir.filename().string(), "suite name");
  refuseControlCharacters(out_dir.string(), "results folder");
  refuseControlCharacters(suite, "--suite");
  refuseControlCharacters(exe.string(), "slamprep binary path");
  refuseControlCharacters(workdir.string(), "working directory");
  refuseControlCharacters(params.results_root.string(), "--results");
  SlurmScripts scripts{out_dir / "slurm" / "shard.sh", out_dir / "slurm" / "merge.sh",
                       out_dir / "slurm"};
  fs::create_directories(scripts.log_dir);
  writeFileAtomic(scripts.shard_script, shardScript(params, out_dir, exe, workdir, suite));
  writeFileAtomic(scripts.merge_script, mergeScript(params, out_dir, exe, workdir));
  for (const auto& f : {scripts.shard_script, scripts.merge_script})
    fs::permissions(f, fs::perms::owner_exec | fs::perms::group_exec | fs::perms::others_exec,
                    fs::perm_options::add);
  return scripts;
}

SlurmResult submitToSlurm(const SlurmParams& params) {
  if (params.shards < 1) throw InputError("--shards", "must be at least 1");
  SlurmParams p = params;
  p.results_root = fs::absolute(params.results_root).lexically_normal();
  const Suite suite = loadSuite(findSuite(p.suite_arg, resolveDataPath("eval/suites")));
  checkSuiteFiles(suite);  // before a job is queued
  const fs::path out_dir = p.results_root / suite.name;

  claimResultsFolder(out_dir, "--results");  // the shards and the merge write into it
  SlurmResult result;
  result.scripts = writeSlurmScripts(p, out_dir);
  result.shards_submitted = incompleteShards(suite, out_dir, p.shards);
  if (!result.shards_submitted.empty()) {
    result.array_job_id =
        submit({"sbatch", "--parsable", "--array=" + joinShards(result.shards_submitted)}, p,
               result.scripts.shard_script);
    result.merge_job_id =
        submit({"sbatch", "--parsable", "--dependency=afterok:" + result.array_job_id,
                "--kill-on-invalid-dep=yes"},
               p, result.scripts.merge_script);
  } else {
    result.merge_job_id = submit({"sbatch", "--parsable"}, p, result.scripts.merge_script);
  }
  result.ok = true;
  return result;
}

void waitForSlurm(const SlurmParams& params, SlurmResult& result) {
  const SlurmParams& p = params;
  waitForJobs(p, result);
  std::string reason;
  for (int k : result.failed_shards)
    reason += (reason.empty() ? "" : "; ") + ("shard " + Shard{k, p.shards}.name()) + " (job " +
              result.array_job_id + "_" + std::to_string(k) + ") failed, log " +
              (result.scripts.log_dir /
               ("shard-" + std::to_string(k) + "-of-" + std::to_string(p.shards) + ".log"))
                  .string();
  if (result.merge_state != "COMPLETED")
    reason += (reason.empty() ? "" : "; ") +
              ("merge job " + result.merge_job_id + " " + result.merge_state + ", log " +
               (result.scripts.log_dir / "merge.log").string());
  result.ok = reason.empty();
  result.reason = reason;
}

}  // namespace slamprep::eval
