#include "slamprep/eval/bench/matching_record.hpp"

#include <numbers>

#include "slamprep/algo/calibration/dataset_motion.hpp"
#include "slamprep/eval/bench/record_fields.hpp"
#include "slamprep/eval/pipeline/match_run.hpp"

namespace slamprep::eval {
namespace {

std::string key(MatchingField field) {
  return keyOf(kMatchingFieldKeys, field);
}

}  // namespace

MatchingRecord matchingRecord(const Dataset& dataset, const CalibrationMotion& motion) {
  const ScanMatchError e = scanMatchError(motion.matches, algo::lidarPosesFromGroundTruth(dataset));
  MatchingRecord r;
  r.pairs = e.pairs;
  r.converged_fraction = e.pairs > 0 ? static_cast<double>(e.converged) / e.pairs : 0.0;
  if (e.translation_m.ok)
    r.error = MatchErrorRecord{e.translation_m.mean, e.translation_m.rmse, e.rotation_deg.mean,
                               e.rotation_deg.rmse};
  if (motion.loops)
    r.loop_closure =
        LoopClosureRecord{motion.loops->used, motion.loops->candidates,
                          motion.loops->max_link_change_rad * 180.0 / std::numbers::pi};
  return r;
}

void to_json(nlohmann::json& out, const MatchingRecord& r) {
  out = {{key(MatchingField::kPairs), r.pairs},
         {key(MatchingField::kConvergedFraction), r.converged_fraction}};
  if (r.error) {
    out[key(MatchingField::kTransErrorMean)] = r.error->trans_error_m_mean;
    out[key(MatchingField::kTransErrorRmse)] = r.error->trans_error_m_rmse;
    out[key(MatchingField::kRotErrorMean)] = r.error->rot_error_deg_mean;
    out[key(MatchingField::kRotErrorRmse)] = r.error->rot_error_deg_rmse;
  }
  if (const auto& l = r.loop_closure)
    out[key(MatchingField::kLoopClosure)] = {
        {key(MatchingField::kLoopsUsed), l->used},
        {key(MatchingField::kLoopCandidates), l->candidates},
        {key(MatchingField::kMaxLinkChange), l->max_link_change_deg}};
}

void from_json(const nlohmann::json& in, MatchingRecord& r) {
  r.pairs = readField<std::size_t>(in, key(MatchingField::kPairs));
  r.converged_fraction = readField<double>(in, key(MatchingField::kConvergedFraction));
  r.error.reset();
  if (in.contains(key(MatchingField::kTransErrorMean)))
    r.error = MatchErrorRecord{readField<double>(in, key(MatchingField::kTransErrorMean)),
                               readField<double>(in, key(MatchingField::kTransErrorRmse)),
                               readField<double>(in, key(MatchingField::kRotErrorMean)),
                               readField<double>(in, key(MatchingField::kRotErrorRmse))};
  r.loop_closure.reset();
  if (in.contains(key(MatchingField::kLoopClosure))) {
    const nlohmann::json& l = in.at(key(MatchingField::kLoopClosure));
    r.loop_closure = LoopClosureRecord{readField<int>(l, key(MatchingField::kLoopsUsed)),
                                       readField<int>(l, key(MatchingField::kLoopCandidates)),
                                       readField<double>(l, key(MatchingField::kMaxLinkChange))};
  }
}

}  // namespace slamprep::eval
