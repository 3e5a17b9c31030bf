#include "slamprep/eval/pipeline/deskew_figures.hpp"

namespace slamprep::eval {
namespace {

/// One field of optional error statistics.
std::optional<double> field(const std::optional<ErrorStats>& stats, double ErrorStats::*member) {
  return stats ? std::optional<double>((*stats).*member) : std::nullopt;
}

}  // namespace

DeskewFigures deskewFigures(const DatasetDeskew& d) {
  DeskewFigures f;
  f.mean_m = field(d.error_m, &ErrorStats::mean);
  f.rms_m = field(d.error_m, &ErrorStats::rmse);
  f.p95_m = field(d.error_m, &ErrorStats::p95);
  f.max_m = field(d.error_m, &ErrorStats::max);
  // The split by cause exists only when every measured scan had its pose errors (both parts).
  const bool split = d.rotation_induced_m && d.translation_induced_m;
  const std::optional<ErrorStats> rotation = split ? d.rotation_induced_m : std::nullopt;
  const std::optional<ErrorStats> translation = split ? d.translation_induced_m : std::nullopt;
  f.rotation_mean_m = field(rotation, &ErrorStats::mean);
  f.rotation_p95_m = field(rotation, &ErrorStats::p95);
  f.translation_mean_m = field(translation, &ErrorStats::mean);
  f.translation_p95_m = field(translation, &ErrorStats::p95);
  if (split) f.split_residual_max_m = d.max_split_residual_m;
  f.repacked_mean_m = field(d.repacked_error_m, &ErrorStats::mean);
  f.repacked_p95_m = field(d.repacked_error_m, &ErrorStats::p95);
  if (d.repacked_error_m) f.repacked_lost_beams = d.repacked_lost_beams;
  if (d.error_m) f.beams = d.error_m->count;
  return f;
}

}  // namespace slamprep::eval
