#include "slamprep/eval/bench/stamps_record.hpp"

#include "slamprep/eval/bench/record_fields.hpp"

namespace slamprep::eval {

StampsRecord stampsRecord(const std::vector<algo::StreamStamps>& streams) {
  StampsRecord out;
  for (const algo::StreamStamps& s : streams)
    out[s.stream] = {s.applied,        s.reason,         s.samples,        s.period_s,
                     s.residual_rms_s, s.residual_max_s, s.missing_samples};
  return out;
}

void to_json(nlohmann::json& out, const StreamStampsRecord& r) {
  out = {{"applied", r.applied},
         {"reason", r.reason},
         {"samples", r.samples},
         {"period_s", r.period_s},
         {"residual_rms_s", r.residual_rms_s},
         {"residual_max_s", r.residual_max_s},
         {"missing_samples", r.missing_samples}};
}

void from_json(const nlohmann::json& in, StreamStampsRecord& r) {
  r.applied = readField<bool>(in, "applied");
  r.reason = readField<std::string>(in, "reason");
  r.samples = readField<std::size_t>(in, "samples");
  r.period_s = readField<double>(in, "period_s");
  r.residual_rms_s = readField<double>(in, "residual_rms_s");
  r.residual_max_s = readField<double>(in, "residual_max_s");
  r.missing_samples = readField<std::size_t>(in, "missing_samples");
}

}  // namespace slamprep::eval
