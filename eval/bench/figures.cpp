#include "slamprep/eval/bench/figures.hpp"

#include <algorithm>
#include <array>
#include <map>

#include "slamprep/core/atomic_file.hpp"
#include "slamprep/core/json_input.hpp"
#include "slamprep/core/paths.hpp"
#include "slamprep/eval/bench/consistency_figure.hpp"
#include "slamprep/eval/bench/figure_groups.hpp"
#include "slamprep/eval/bench/figures_internal.hpp"
#include "slamprep/eval/bench/runner.hpp"
#include "slamprep/eval/bench/summary.hpp"
#include "slamprep/eval/bench/trial_record.hpp"
#include "slamprep/eval/plot/plot.hpp"

namespace slamprep::eval {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

constexpr int kMinSeedsForConsistency = 20;

// The figures drawn from the first trial's artifacts under trials/, in README order.
constexpr std::array<const char*, 3> kArtifactPlots = {"trajectory.png", "odometry_error.png",
                                                       "scan.png"};

// The first trial's artifacts (trajectories, one scan, odometry error), if recorded.
std::optional<ArtifactsRecord> firstArtifacts(const Suite& suite, const fs::path& out_dir) {
  const auto trials = expandTrials(suite);
  const auto file = out_dir / "trials" / (trials.front().id + ".json");
  if (!fs::exists(file)) return std::nullopt;
  const json trial = readJsonFile(file, "trial result");
  const std::string key = sectionKey(TrialSection::kArtifacts);
  if (!trial.is_object() || !trial.contains(key)) return std::nullopt;
  return trial[key].get<ArtifactsRecord>();
}

// Each group's rows of trials.csv (its seeds): a trial's id names its spec in the suite, whose
// groupKey makes the group (summarize). `rows` and `ids` are trials.csv's, in its order.
std::vector<TrialRows> trialRowsByGroup(const Suite& suite, const std::vector<SummaryGroup>& groups,
                                        const TrialRows& rows,
                                        const std::vector<std::string>& ids) {
  std::map<std::string, TrialSpec> spec_of_id;
  for (TrialSpec& spec : expandTrials(suite)) spec_of_id[spec.id] = std::move(spec);
  std::vector<TrialRows> by_group(groups.size());
  for (std::size_t r = 0; r < rows.size() && r < ids.size(); ++r) {
    const auto it = spec_of_id.find(ids[r]);
    if (it == spec_of_id.end()) continue;  // a trial the suite no longer has
    const TrialSpec& spec = it->second;
    for (std::size_t g = 0; g < groups.size(); ++g)
      if (groups[g].world == spec.world && groups[g].scenario == spec.scenario &&
          groups[g].sweep == spec.sweep)
        by_group[g].push_back(rows[r]);
  }
  return by_group;
}

// Without trials/ nothing can redraw the artifact figures: keep the PNGs already there (never
// lose a user's data) rather than drop them from the README.
void keepArtifactPlots(const fs::path& plots_dir, SuitePlots& plots) {
  for (const char* name : kArtifactPlots)
    if (fs::exists(plots_dir / name)) {
      plots.names.emplace_back(name);
      plots.kept.emplace_back(name);
    }
}

bool sweeps(const Suite& suite, const std::string& key) {
  return std::any_of(suite.sweep.begin(), suite.sweep.end(),
                     [&](const SweepAxis& a) { return a.key == key; });
}

}  // namespace

SuitePlots renderSuitePlots(const Suite& suite, const SuiteSummary& summary,
                            const fs::path& out_dir) {
  std::vector<std::pair<std::string, plot::Figure>> figures;
  const std::vector<SummaryGroup>& groups = summary.groups;
  const TrialRows trial_rows = readTrialRows(out_dir / "trials.csv");  // empty without the file
  if (!deskewMethodsIn(groups).empty()) {
    // A scenario series (speeds) is a sweep: lines along it. Otherwise one panel per condition.
    if (auto fig = deskewVsSpeedFigure(groups))
      figures.emplace_back("deskew_vs_speed.png", std::move(*fig));
    else
      figures.emplace_back("deskew_by_method.png", deskewFigure(groups));
  }
  if (!calibrationMethodsIn(groups).empty()) {
    if (sweeps(suite, "duration_s"))
      figures.emplace_back("calibration_vs_time.png", calibrationVsTimeFigure(groups));
    else
      figures.emplace_back(
          "calibration_error.png",
          calibrationFigure(groups, trialRowsByGroup(suite, groups, trial_rows,
                                                     readTrialIds(out_dir / "trials.csv"))));
  }
  // error/sigma histograms need many seeds of one experiment to say anything (the seeds suite).
  // It pools every trial of trials.csv, so only where they share one condition (one group).
  if (suite.seeds >= kMinSeedsForConsistency && groups.size() == 1)
    if (auto fig = consistencyFigure(trial_rows))
      figures.emplace_back("consistency.png", std::move(*fig));
  if (const auto artifacts = firstArtifacts(suite, out_dir)) {
    figures.emplace_back("trajectory.png", trajectoryFigure(suite, artifacts->trajectory));
    figures.emplace_back("odometry_error.png", odometryErrorFigure(artifacts->odometry_error));
    if (artifacts->scan) figures.emplace_back("scan.png", scanFigure(suite, *artifacts->scan));
  }
  SuitePlots plots;
  fs::create_directories(out_dir / "plots");
  for (const auto& [name, figure] : figures) {
    plot::renderPng(figure, out_dir / "plots" / name);
    plots.names.push_back(name);
  }
  if (!fs::exists(out_dir / "trials")) keepArtifactPlots(out_dir / "plots", plots);
  return plots;
}

}  // namespace slamprep::eval
