#include "slamprep/eval/bench/trial_record.hpp"

#include "slamprep/eval/bench/record_fields.hpp"

namespace slamprep::eval {
namespace {

using nlohmann::json;

std::string key(OdometryGeometry geometry) {
  return keyOf(kOdometryGeometryKeys, geometry);
}

// Writes a map section only when it has entries.
template <typename Map>
void writeMap(json& out, TrialSection section, const Map& map) {
  if (!map.empty()) out[sectionKey(section)] = map;
}

// Reads a map section when present.
template <typename Map>
Map readMap(const json& in, TrialSection section) {
  return in.contains(sectionKey(section)) ? in.at(sectionKey(section)).get<Map>() : Map{};
}

}  // namespace

std::string sectionKey(TrialSection section) {
  return keyOf(kTrialSectionKeys, section);
}

void to_json(json& out, const TrialRecord& r) {
  out = {{sectionKey(TrialSection::kSim), r.sim},
         {sectionKey(TrialSection::kOdometry),
          {{key(OdometryGeometry::kNominal), r.odometry_nominal},
           {key(OdometryGeometry::kTrue), r.odometry_true}}}};
  writeMap(out, TrialSection::kStamps, r.stamps);
  writeMap(out, TrialSection::kFaults, r.faults);
  writeOptional(out, sectionKey(TrialSection::kMatching), r.matching);
  writeMap(out, TrialSection::kCalibration, r.calibration);
  writeMap(out, TrialSection::kDeskew, r.deskew);
  writeOptional(out, sectionKey(TrialSection::kArtifacts), r.artifacts);
  if (!r.trial.is_null()) out[sectionKey(TrialSection::kTrial)] = r.trial;
}

void from_json(const json& in, TrialRecord& r) {
  r.sim = readField<SimRecord>(in, sectionKey(TrialSection::kSim));
  r.stamps = readMap<StampsRecord>(in, TrialSection::kStamps);
  r.faults = readMap<std::map<std::string, std::size_t>>(in, TrialSection::kFaults);
  const json& odometry = in.at(sectionKey(TrialSection::kOdometry));
  r.odometry_nominal = readField<OdometryRecord>(odometry, key(OdometryGeometry::kNominal));
  r.odometry_true = readField<OdometryRecord>(odometry, key(OdometryGeometry::kTrue));
  r.matching = readOptional<MatchingRecord>(in, sectionKey(TrialSection::kMatching));
  r.calibration = calibrationRecords(in);
  r.deskew = readMap<std::map<std::string, DeskewRecord>>(in, TrialSection::kDeskew);
  r.artifacts = readOptional<ArtifactsRecord>(in, sectionKey(TrialSection::kArtifacts));
  r.trial = in.value(sectionKey(TrialSection::kTrial), json());
}

std::map<std::string, CalibrationRecord> calibrationRecords(const json& result) {
  return readMap<std::map<std::string, CalibrationRecord>>(result, TrialSection::kCalibration);
}

}  // namespace slamprep::eval
