// `slamprep score`: trajectory scores on files (docs/score.md). `relations`: the relation metric
// of Kümmerle et al. 2009 of a TUM trajectory against a benchmark relations file; `ape`/`rpe`:
// evo's APE and RPE of a TUM estimate against a TUM ground truth.
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "slamprep/app/choices.hpp"
#include "slamprep/app/commands.hpp"
#include "slamprep/app/common_flags.hpp"
#include "slamprep/app/outputs.hpp"
#include "slamprep/core/atomic_file.hpp"
#include "slamprep/core/error.hpp"
#include "slamprep/eval/formats/relations.hpp"
#include "slamprep/eval/formats/tum.hpp"
#include "slamprep/eval/metrics/relation_error.hpp"
#include "slamprep/eval/metrics/trajectory_error.hpp"

namespace slamprep::app {
namespace {

struct ScoreFlags : CommonFlags {
  std::string first, second;  // relations or ground truth; trajectory or estimate
  eval::RelationErrorParams relations;
  std::string align = "rigid";
  eval::ApeParams ape;
  std::string unit = "frames";
  eval::RpeParams rpe;
};

nlohmann::ordered_json statsJson(const eval::ErrorStats& s) {
  if (!s.ok) return nullptr;
  return {{"count", s.count}, {"mean", s.mean}, {"std", s.std},       {"min", s.min},
          {"max", s.max},     {"rmse", s.rmse}, {"median", s.median}, {"p95", s.p95}};
}

void writeJson(const std::string& file, const nlohmann::ordered_json& j) {
  if (!file.empty()) writeFileAtomic(file, j.dump(2) + "\n");
}

/// One table row: mean, std and max of a statistic, or dashes when the set is empty.
std::string cells(const eval::ErrorStats& s) {
  char text[64];
  if (!s.ok) return "       -        -        -";
  std::snprintf(text, sizeof text, " %8.4f %8.4f %8.4f", s.mean, s.std, s.max);
  return text;
}

int runRelations(const ScoreFlags& f) {
  const auto relations = eval::readRelations(f.first);
  const PoseSeries trajectory = eval::readTum(f.second);
  const eval::RelationErrorResult r = eval::relationError(trajectory, relations, f.relations);
  if (!r.ok) throw InputError(f.second + " against " + f.first, r.reason);
  std::printf(
      "%zu relations in %s: %zu scored, %zu skipped (stamps the trajectory does not "
      "cover within %g s)\n",
      r.relations, f.first.c_str(), r.scored.size(), r.uncovered,
      f.relations.max_time_difference_s);
  std::printf("%-20s %26s   %26s\n", "", ("all (" + std::to_string(r.scored.size()) + ")").c_str(),
              ("< " + std::to_string(int(f.relations.short_relation_s)) + " s apart (" +
               std::to_string(r.short_count) + ")")
                  .c_str());
  std::printf("%-20s %8s %8s %8s   %8s %8s %8s\n", "", "mean", "std", "max", "mean", "std", "max");
  const auto row = [](const char* name, const eval::ErrorStats& a, const eval::ErrorStats& b) {
    std::printf("%-20s%s  %s\n", name, cells(a).c_str(), cells(b).c_str());
  };
  row("translation [m]", r.all.translation_m, r.short_span.translation_m);
  row("translation^2 [m^2]", r.all.translation_sq_m2, r.short_span.translation_sq_m2);
  row("rotation [deg]", r.all.rotation_deg, r.short_span.rotation_deg);
  row("rotation^2 [deg^2]", r.all.rotation_sq_deg2, r.short_span.rotation_sq_deg2);
  const auto set = [](const eval::RelationStats& s) {
    return nlohmann::ordered_json{{"translation_m", statsJson(s.translation_m)},
                                  {"translation_sq_m2", statsJson(s.translation_sq_m2)},
                                  {"rotation_deg", statsJson(s.rotation_deg)},
                                  {"rotation_sq_deg2", statsJson(s.rotation_sq_deg2)}};
  };
  writeJson(f.json_out, {{"metric", "relations"},
                         {"relations_file", f.first},
                         {"trajectory_file", f.second},
                         {"max_time_difference_s", f.relations.max_time_difference_s},
                         {"short_relation_s", f.relations.short_relation_s},
                         {"relations", r.relations},
                         {"scored", r.scored.size()},
                         {"uncovered", r.uncovered},
                         {"short_scored", r.short_count},
                         {"all", set(r.all)},
                         {"short", set(r.short_span)}});
  return 0;
}

void printPair(const char* what, std::size_t n, const eval::ErrorStats& t,
               const eval::ErrorStats& r) {
  std::printf(
      "%s over %zu: translation [m] mean %.6g rmse %.6g max %.6g; rotation [deg] mean "
      "%.6g rmse %.6g max %.6g\n",
      what, n, t.mean, t.rmse, t.max, r.mean, r.rmse, r.max);
}

int runApe(ScoreFlags f) {
  f.ape.align = f.align == "rigid";
  f.ape.align_origin = f.align == "origin";
  const eval::ApeResult r =
      eval::absolutePoseError(eval::readTum(f.second), eval::readTum(f.first), f.ape);
  if (!r.ok) throw InputError(f.second + " against " + f.first, r.reason);
  printPair("APE", r.matched, r.translation_m, r.rotation_deg);
  std::printf("(%zu estimate poses without ground truth within %g s; alignment %s)\n", r.unmatched,
              f.ape.max_time_difference_s, f.align.c_str());
  writeJson(f.json_out, {{"metric", "ape"},
                         {"groundtruth_file", f.first},
                         {"estimate_file", f.second},
                         {"align", f.align},
                         {"max_time_difference_s", f.ape.max_time_difference_s},
                         {"matched", r.matched},
                         {"unmatched", r.unmatched},
                         {"T_ref_est", {r.T_ref_est.x, r.T_ref_est.y, r.T_ref_est.yaw}},
                         {"translation_m", statsJson(r.translation_m)},
                         {"rotation_deg", statsJson(r.rotation_deg)}});
  return 0;
}

int runRpe(ScoreFlags f) {
  f.rpe.unit = parseName(eval::kDeltaUnitNames, f.unit, "delta unit", "--unit");
  const eval::RpeResult r =
      eval::relativePoseError(eval::readTum(f.second), eval::readTum(f.first), f.rpe);
  if (!r.ok) throw InputError(f.second + " against " + f.first, r.reason);
  printPair("RPE", r.pairs, r.translation_m, r.rotation_deg);
  std::printf("(pairs %g %s apart%s; %zu estimate poses without ground truth within %g s)\n",
              f.rpe.delta, f.unit.c_str(), f.rpe.all_pairs ? ", all pairs" : "", r.unmatched,
              f.rpe.max_time_difference_s);
  writeJson(f.json_out, {{"metric", "rpe"},
                         {"groundtruth_file", f.first},
                         {"estimate_file", f.second},
                         {"delta", f.rpe.delta},
                         {"unit", f.unit},
                         {"all_pairs", f.rpe.all_pairs},
                         {"max_time_difference_s", f.rpe.max_time_difference_s},
                         {"pairs", r.pairs},
                         {"unmatched", r.unmatched},
                         {"translation_m", statsJson(r.translation_m)},
                         {"rotation_deg", statsJson(r.rotation_deg)}});
  return 0;
}

}  // namespace

Command addScoreCommand(CLI::App& app) {
  auto flags = std::make_shared<ScoreFlags>();
  auto* cli = app.add_subcommand("score", "Score a TUM trajectory: relations, APE or RPE.");
  cli->require_subcommand(1);
  auto* rel = cli->add_subcommand(
      "relations", "Relation metric of Kümmerle et al. 2009 (SLAM benchmark relations files).");
  rel->add_option("RELATIONS", flags->first, "relations file (t1 t2 x y z roll pitch yaw)")
      ->required();
  rel->add_option("TRAJ", flags->second, "TUM trajectory")->required();
  rel->add_option("--max-time-difference", flags->relations.max_time_difference_s,
                  "interpolate between samples at most this far (s) from a relation stamp")
      ->check(nonNegative())
      ->capture_default_str();
  rel->add_option("--short", flags->relations.short_relation_s,
                  "relations under this many seconds apart form the short subset")
      ->check(positive())
      ->capture_default_str();
  auto* ape = cli->add_subcommand("ape", "Absolute pose error (evo's definition).");
  auto* rpe = cli->add_subcommand("rpe", "Relative pose error (evo's definition).");
  for (auto* sub : {ape, rpe}) {
    sub->add_option("GROUNDTRUTH", flags->first, "TUM reference trajectory")->required();
    sub->add_option("ESTIMATE", flags->second, "TUM estimate")->required();
  }
  ape->add_option("--align", flags->align, "rigid (evo -a), origin (evo --align_origin) or none")
      ->check(oneOf("alignment", {"rigid", "origin", "none"}))
      ->capture_default_str();
  ape->add_option("--max-time-difference", flags->ape.max_time_difference_s,
                  "association tolerance (s)")
      ->check(nonNegative())
      ->capture_default_str();
  rpe->add_option("--delta", flags->rpe.delta, "pose-pair spacing")
      ->check(positive())
      ->capture_default_str();
  rpe->add_option("--unit", flags->unit, "frames or m")
      ->check(oneOf("delta unit", namesOf(eval::kDeltaUnitNames)))
      ->capture_default_str();
  rpe->add_flag("--all-pairs", flags->rpe.all_pairs, "every start pose, not consecutive segments");
  rpe->add_option("--max-time-difference", flags->rpe.max_time_difference_s,
                  "association tolerance (s)")
      ->check(nonNegative())
      ->capture_default_str();
  for (auto* sub : {rel, ape, rpe}) {
    addJson(sub, *flags, "the figures");
    addForce(sub, *flags, "an existing --json file");
  }
  return {cli, [flags, rel, ape] {
            if (!flags->json_out.empty())
              OutputGuard(flags->force)
                  .input(flags->first, rel->parsed() ? "RELATIONS" : "GROUNDTRUTH")
                  .input(flags->second, rel->parsed() ? "TRAJ" : "ESTIMATE")
                  .file(flags->json_out, "--json")
                  .check();
            if (rel->parsed()) return runRelations(*flags);
            if (ape->parsed()) return runApe(*flags);
            return runRpe(*flags);
          }};
}

}  // namespace slamprep::app
