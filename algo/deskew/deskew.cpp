// The dispatcher: checks the scan, finds the method's knots T_Lref_L(t) (method.hpp), and moves
// every beam with them (beam_transform.hpp).
#include "slamprep/algo/deskew/deskew.hpp"

#include <array>
#include <cmath>

#include "slamprep/algo/deskew/method.hpp"

namespace slamprep::algo {
namespace {

/// The series a method needs, as bits.
enum Needs : unsigned { kNoSeries = 0, kTruth = 1, kOdometry = 2, kImu = 4 };

struct MethodEntry {
  DeskewMethod method;
  Trajectory (*knots)(const MethodCall&);
  bool uses_previous_scan;
  unsigned needs;  ///< Needs bits: deskewMissingInput()
};
constexpr std::array<MethodEntry, 8> kMethods{{
    {DeskewMethod::kNone, noneKnots, false, kNoSeries},
    {DeskewMethod::kOracle, oracleKnots, false, kTruth},
    {DeskewMethod::kConstVelocity, constVelocityKnots, true, kNoSeries},
    {DeskewMethod::kVicp, vicpKnots, true, kNoSeries},
    {DeskewMethod::kOdomLinear, odomLinearKnots, false, kOdometry},
    {DeskewMethod::kOdomQuadratic, odomQuadraticKnots, false, kOdometry},
    {DeskewMethod::kImu, imuKnots, false, kOdometry | kImu},
    {DeskewMethod::kOdomIcp, odomIcpKnots, true, kOdometry},
}};
// One order for the methods: allDeskewMethods() follows kMethods, the names kDeskewMethodNames.
static_assert([] {
  for (std::size_t i = 0; i < kMethods.size(); ++i)
    if (kMethods[i].method != kDeskewMethodNames.at(i).first) return false;
  return kMethods.size() == kDeskewMethodNames.size();
}());

const MethodEntry* entry(DeskewMethod method) {
  for (const auto& m : kMethods)
    if (m.method == method) return &m;
  return nullptr;
}

}  // namespace

const std::vector<DeskewMethod>& allDeskewMethods() {
  static const std::vector<DeskewMethod> all = [] {
    std::vector<DeskewMethod> v;
    for (const auto& m : kMethods) v.push_back(m.method);
    return v;
  }();
  return all;
}

std::string_view deskewMethodName(DeskewMethod method) {
  return nameOf(kDeskewMethodNames, method);
}

std::optional<DeskewMethod> parseDeskewMethod(std::string_view name) {
  return findName(kDeskewMethodNames, name);
}

bool deskewMethodUsesPreviousScan(DeskewMethod method) {
  const MethodEntry* m = entry(method);
  return m && m->uses_previous_scan;
}

std::string_view deskewInputName(DeskewInput input) {
  return nameOf(kDeskewInputNames, input);
}

std::optional<DeskewInput> deskewMissingInput(DeskewMethod method, DeskewInputsGiven given) {
  const MethodEntry* m = entry(method);
  const unsigned needs = m ? m->needs : kNoSeries;
  if ((needs & kTruth) && !given.groundtruth) return DeskewInput::kGroundTruth;
  if ((needs & kOdometry) && !given.odometry) return DeskewInput::kOdometry;
  if ((needs & kImu) && !given.imu) return DeskewInput::kImu;
  return std::nullopt;
}

const std::vector<DeskewRefusal>& allDeskewRefusals() {
  static const std::vector<DeskewRefusal> all = [] {
    std::vector<DeskewRefusal> v;
    for (const auto& [reason, name] : kDeskewRefusalNames)
      if (reason != DeskewRefusal::kNone) v.push_back(reason);
    return v;
  }();
  return all;
}

std::string_view deskewRefusalName(DeskewRefusal reason) {
  return nameOf(kDeskewRefusalNames, reason);
}

std::string_view referenceTimeName(ReferenceTime reference) {
  return nameOf(kReferenceTimeNames, reference);
}

std::optional<ReferenceTime> parseReferenceTime(std::string_view name) {
  return findName(kReferenceTimeNames, name);
}

double firstBeamTime(const LaserScan& scan, bool stamp_is_last_beam) {
  if (!stamp_is_last_beam || scan.size() == 0) return scan.stamp_s;
  return scan.stamp_s - (scan.size() - 1) * scan.time_increment_s;
}

std::optional<std::string> checkBracketing(const LaserScan& scan, bool stamp_is_last_beam,
                                           const PoseSeries& poses, std::string_view what) {
  const double duration = (scan.size() > 0 ? scan.size() - 1 : 0) * scan.time_increment_s;
  const double first = firstBeamTime(scan, stamp_is_last_beam), last = first + duration;
  if (poses.covers(first) && poses.covers(last)) return std::nullopt;
  std::string message =
      std::string(what) + " does not bracket the scan [" + fmt(first) + ", " + fmt(last) + "] s";
  message += poses.empty() ? " (it is empty)"
                           : " (it covers [" + fmt(poses.frontStamp()) + ", " +
                                 fmt(poses.backStamp()) + "] s)";
  const double other_first = firstBeamTime(scan, !stamp_is_last_beam);
  if (poses.covers(other_first) && poses.covers(other_first + duration))
    message += stamp_is_last_beam
                   ? "; it would if the stamp marked the first beam: is stamp_is_last_beam wrong?"
                   : "; it would if the stamp marked the last beam: set stamp_is_last_beam";
  return message;
}

DeskewResult deskew(DeskewMethod method, const LaserScan& scan, const DeskewInputs& inputs,
                    const DeskewParams& params) {
  DeskewResult result;
  if (scan.size() == 0) {
    result.refusal = DeskewRefusal::kNoBeams;
    result.reason = "the scan has no beams";
    return result;
  }
  if (!(scan.time_increment_s > 0.0) || !std::isfinite(scan.time_increment_s)) {
    result.refusal = DeskewRefusal::kNoBeamTimes;
    result.reason = "time_increment is " + fmt(scan.time_increment_s) +
                    ": the beam times are unknown, so the scan cannot be de-skewed";
    return result;
  }
  const MethodEntry* m = entry(method);
  if (!m) {
    result.refusal = DeskewRefusal::kUnknownMethod;
    result.reason = "unknown method";
    return result;
  }
  const ScanTimes t = scanTimes(scan, inputs.stamp_is_last_beam, inputs.reference);
  result.first_beam_s = t.first_s;
  result.reference_s = t.ref_s;
  const DeskewInputsGiven given{!inputs.groundtruth.empty(), !inputs.odometry.empty(),
                                !inputs.imu.empty()};
  if (const auto missing = deskewMissingInput(method, given)) {
    result.refusal = DeskewRefusal::kMissingInput;
    result.reason = std::string(deskewMethodName(method)) + " needs " +
                    std::string(deskewInputName(*missing)) + ", none was given";
    return result;
  }
  try {
    result.T_ref_lidar = m->knots({method, scan, t, inputs, params, result});
    transformBeams(scan, t.first_s, result.T_ref_lidar, result.p_ref);
    // The first-beam frame seen from the reference frame is the knots' value at t_first.
    result.T_first_ref = poseAt(result.T_ref_lidar, t.first_s).inverse();
  } catch (const Refusal& refusal) {
    result.p_ref.clear();
    result.T_ref_lidar.clear();
    result.refusal = refusal.code;
    result.reason = refusal.reason;
    return result;
  }
  if (params.repack) {
    result.repacked = repackOnGrid(scan, result.p_ref, params.repacking).scan;
    result.repacked.stamp_s = t.ref_s;
    result.repacked.time_increment_s = 0.0;
  }
  result.ok = true;
  return result;
}

}  // namespace slamprep::algo
