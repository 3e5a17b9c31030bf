#include "eval/pipeline/deskew_json.hpp"

#include <optional>
#include <string>

namespace slamprep::eval {
namespace {

using Json = nlohmann::ordered_json;

/// Appends `key`: `value` when there is a value, else null or nothing as `absent` says.
void put(Json& out, const char* key, const std::optional<Json>& value, AbsentFigure absent) {
  if (value)
    out[key] = *value;
  else if (absent == AbsentFigure::kNull)
    out[key] = nullptr;
}

/// One field of optional error statistics.
std::optional<Json> field(const std::optional<ErrorStats>& stats, double ErrorStats::*member) {
  return stats ? std::optional<Json>((*stats).*member) : std::nullopt;
}

}  // namespace

Json deskewFiguresJson(const DatasetDeskew& d, AbsentFigure absent) {
  Json out = Json::object();
  put(out, "mean_m", field(d.error_m, &ErrorStats::mean), absent);
  put(out, "rms_m", field(d.error_m, &ErrorStats::rmse), absent);
  put(out, "p95_m", field(d.error_m, &ErrorStats::p95), absent);
  put(out, "max_m", field(d.error_m, &ErrorStats::max), absent);
  // The split by cause exists only when every measured scan had its pose errors (both parts).
  const bool split = d.rotation_induced_m && d.translation_induced_m;
  const std::optional<ErrorStats> rotation = split ? d.rotation_induced_m : std::nullopt;
  const std::optional<ErrorStats> translation = split ? d.translation_induced_m : std::nullopt;
  put(out, "rotation_mean_m", field(rotation, &ErrorStats::mean), absent);
  put(out, "rotation_p95_m", field(rotation, &ErrorStats::p95), absent);
  put(out, "translation_mean_m", field(translation, &ErrorStats::mean), absent);
  put(out, "translation_p95_m", field(translation, &ErrorStats::p95), absent);
  put(out, "split_residual_max_m",
      split ? std::optional<Json>(d.max_split_residual_m) : std::nullopt, absent);
  put(out, "repacked_mean_m", field(d.repacked_error_m, &ErrorStats::mean), absent);
  put(out, "repacked_p95_m", field(d.repacked_error_m, &ErrorStats::p95), absent);
  put(out, "repacked_lost_beams",
      d.repacked_error_m ? std::optional<Json>(d.repacked_lost_beams) : std::nullopt, absent);
  if (d.error_m)
    out["beams"] = d.error_m->count;
  else if (absent == AbsentFigure::kNull)
    out["beams"] = 0;  // no beam measured
  return out;
}

Json deskewRefusalsJson(const DatasetDeskew& d, std::string_view method) {
  Json out = Json::array();
  for (const auto& r : d.refusals)
    out.push_back({{"scan", r.scan},
                   {"method", std::string(method)},
                   {"reason", std::string(algo::deskewRefusalName(r.reason))},
                   {"detail", r.detail}});
  return out;
}

}  // namespace slamprep::eval
