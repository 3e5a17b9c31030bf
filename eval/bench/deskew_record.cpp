#include "slamprep/eval/bench/deskew_record.hpp"

#include "slamprep/eval/bench/record_fields.hpp"
#include "slamprep/eval/pipeline/deskew_json.hpp"

namespace slamprep::eval {
namespace {

std::string key(DeskewField field) {
  return keyOf(kDeskewFieldKeys, field);
}

}  // namespace

DeskewRecord deskewRecord(const DatasetDeskew& d, const std::string& method) {
  DeskewRecord r;
  r.ok = d.refused == 0;
  r.refused_scans = d.refused;
  if (d.refused) r.refused_by_reason = refusedByReason(d.refusals);
  if (d.refused)
    for (const ScanRefusal& s : d.refusals)
      r.refusals.push_back(
          {s.scan, method, std::string(algo::deskewRefusalName(s.reason)), s.detail});
  r.figures = deskewFigures(d);
  return r;
}

void to_json(nlohmann::json& out, const DeskewRecord& r) {
  out = {{key(DeskewField::kOk), r.ok}};
  if (r.refused_scans) {
    out[key(DeskewField::kRefusedScans)] = r.refused_scans;
    out[key(DeskewField::kRefusedByReason)] = r.refused_by_reason;
    out[key(DeskewField::kRefusals)] = r.refusals;
  }
  out.update(nlohmann::json(deskewFiguresJson(r.figures, AbsentFigure::kOmitted)));
}

void from_json(const nlohmann::json& in, DeskewRecord& r) {
  r.ok = readField<bool>(in, key(DeskewField::kOk));
  r.refused_scans = in.value(key(DeskewField::kRefusedScans), 0);
  r.refused_by_reason = in.value(key(DeskewField::kRefusedByReason), std::map<std::string, int>{});
  r.refusals = in.value(key(DeskewField::kRefusals), std::vector<DeskewRefusalRecord>{});
  r.figures = deskewFiguresFromJson(in, AbsentFigure::kOmitted);
}

void to_json(nlohmann::json& out, const DeskewRefusalRecord& r) {
  out = {{"scan", r.scan}, {"method", r.method}, {"reason", r.reason}, {"detail", r.detail}};
}

void from_json(const nlohmann::json& in, DeskewRefusalRecord& r) {
  r.scan = readField<std::size_t>(in, "scan");
  r.method = readField<std::string>(in, "method");
  r.reason = readField<std::string>(in, "reason");
  r.detail = readField<std::string>(in, "detail");
}

}  // namespace slamprep::eval
