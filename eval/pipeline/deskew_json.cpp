#include "slamprep/eval/pipeline/deskew_json.hpp"

#include <cmath>
#include <optional>
#include <string>
#include <type_traits>

namespace slamprep::eval {
namespace {

using Json = nlohmann::ordered_json;

std::string key(DeskewFigure figure) {
  return std::string(nameOf(kDeskewFigureKeys, figure));
}

/// Appends the figure when there is a value, else null or nothing as `absent` says.
template <typename T>
void put(Json& out, DeskewFigure figure, const std::optional<T>& value, AbsentFigure absent) {
  if (value)
    out[key(figure)] = *value;
  else if (absent == AbsentFigure::kNull)
    out[key(figure)] = nullptr;
}

/// The figure when present; a null is absent (kNull) or a NaN (kOmitted: nlohmann writes a
/// non-finite number as null).
template <typename T>
std::optional<T> get(const nlohmann::json& in, DeskewFigure figure, AbsentFigure absent) {
  const auto it = in.find(key(figure));
  if (it == in.end() || (it->is_null() && absent == AbsentFigure::kNull)) return std::nullopt;
  if constexpr (std::is_floating_point_v<T>)
    if (it->is_null()) return std::nan("");
  return it->get<T>();
}

}  // namespace

Json deskewFiguresJson(const DeskewFigures& f, AbsentFigure absent) {
  Json out = Json::object();
  put(out, DeskewFigure::kMean, f.mean_m, absent);
  put(out, DeskewFigure::kRms, f.rms_m, absent);
  put(out, DeskewFigure::kP95, f.p95_m, absent);
  put(out, DeskewFigure::kMax, f.max_m, absent);
  put(out, DeskewFigure::kRotationMean, f.rotation_mean_m, absent);
  put(out, DeskewFigure::kRotationP95, f.rotation_p95_m, absent);
  put(out, DeskewFigure::kTranslationMean, f.translation_mean_m, absent);
  put(out, DeskewFigure::kTranslationP95, f.translation_p95_m, absent);
  put(out, DeskewFigure::kSplitResidualMax, f.split_residual_max_m, absent);
  put(out, DeskewFigure::kRepackedMean, f.repacked_mean_m, absent);
  put(out, DeskewFigure::kRepackedP95, f.repacked_p95_m, absent);
  put(out, DeskewFigure::kRepackedLostBeams, f.repacked_lost_beams, absent);
  if (f.beams)
    out[key(DeskewFigure::kBeams)] = *f.beams;
  else if (absent == AbsentFigure::kNull)
    out[key(DeskewFigure::kBeams)] = 0;  // no beam measured
  return out;
}

Json deskewFiguresJson(const DatasetDeskew& d, AbsentFigure absent) {
  return deskewFiguresJson(deskewFigures(d), absent);
}

DeskewFigures deskewFiguresFromJson(const nlohmann::json& in, AbsentFigure absent) {
  return {.mean_m = get<double>(in, DeskewFigure::kMean, absent),
          .rms_m = get<double>(in, DeskewFigure::kRms, absent),
          .p95_m = get<double>(in, DeskewFigure::kP95, absent),
          .max_m = get<double>(in, DeskewFigure::kMax, absent),
          .rotation_mean_m = get<double>(in, DeskewFigure::kRotationMean, absent),
          .rotation_p95_m = get<double>(in, DeskewFigure::kRotationP95, absent),
          .translation_mean_m = get<double>(in, DeskewFigure::kTranslationMean, absent),
          .translation_p95_m = get<double>(in, DeskewFigure::kTranslationP95, absent),
          .split_residual_max_m = get<double>(in, DeskewFigure::kSplitResidualMax, absent),
          .repacked_mean_m = get<double>(in, DeskewFigure::kRepackedMean, absent),
          .repacked_p95_m = get<double>(in, DeskewFigure::kRepackedP95, absent),
          .repacked_lost_beams = get<std::size_t>(in, DeskewFigure::kRepackedLostBeams, absent),
          .beams = get<std::size_t>(in, DeskewFigure::kBeams, absent)};
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
