#include "slamprep/algo/agreement/agreement_report.hpp"

#include <algorithm>
#include <cstdio>
#include <limits>
#include <numbers>

namespace slamprep::algo {
namespace {

constexpr double kDeg = 180.0 / std::numbers::pi;

nlohmann::ordered_json spanJson(const Disagreement& d) {
  return {{"t0_s", d.t0_s},
          {"t1_s", d.t1_s},
          {"turn_a_deg", d.turn_a_rad * kDeg},
          {"turn_b_deg", d.turn_b_rad * kDeg},
          {"max_residual_deg", d.max_residual_rad * kDeg},
          {"likely_cause", d.likely_cause}};
}

nlohmann::ordered_json pairJson(const PairAgreement& p) {
  nlohmann::ordered_json spans = nlohmann::ordered_json::array();
  for (const Disagreement& d : p.disagreements) spans.push_back(spanJson(d));
  nlohmann::ordered_json j = {{"a", p.a},
                              {"b", p.b},
                              {"model", p.model},
                              {"windows", p.windows},
                              {"kept", p.kept},
                              {"lag_s", p.lag_s},
                              {"scale", p.scale},
                              {"bias_degps", p.bias_radps * kDeg},
                              {"rms_residual_deg", p.rms_residual_rad * kDeg},
                              {"sigma_deg", p.sigma_rad * kDeg}};
  if (p.wheel_ratios) j["wheel_ratios"] = {(*p.wheel_ratios)(0), (*p.wheel_ratios)(1)};
  if (p.effective_wheel_base_m) j["effective_wheel_base_m"] = *p.effective_wheel_base_m;
  if (p.travel_rad_per_m) j["travel_deg_per_m"] = *p.travel_rad_per_m * kDeg;
  j["agree"] = p.disagreements.empty();
  j["disagreements"] = spans;
  return j;
}

std::string line(const char* format, auto... args) {
  char buffer[512];
  std::snprintf(buffer, sizeof buffer, format, args...);
  return buffer;
}

/// Spans are printed in seconds from the recording's start (`t_start`); the JSON keeps stamps.
std::string pairText(const PairAgreement& p, double t_start) {
  std::string s = line("  %s vs %s: %zu windows, %s turn %.3fx %s", p.a.c_str(), p.b.c_str(),
                       p.windows, p.a.c_str(), p.scale, p.b.c_str());
  if (p.effective_wheel_base_m)
    s += line(" (wheel base %.1f mm with the nominal radii)", *p.effective_wheel_base_m * 1e3);
  if (p.travel_rad_per_m)
    s += line(" and %.2f deg per m of the odometry's travel", *p.travel_rad_per_m * kDeg);
  if (p.lag_s != 0.0) s += line(", %s %.2f s late", p.b.c_str(), p.lag_s);
  s += line(", rms %.2f deg per window", p.rms_residual_rad * kDeg);
  if (p.disagreements.empty()) return s + ", agree\n";
  s += line(", DISAGREE in %zu span%s:\n", p.disagreements.size(),
            p.disagreements.size() == 1 ? "" : "s");
  for (const Disagreement& d : p.disagreements)
    s += line("    +%.1f..+%.1f s: %s\n", d.t0_s - t_start, d.t1_s - t_start,
              d.likely_cause.c_str());
  return s;
}

double startOf(const SensorAgreement& a) {
  double t = std::numeric_limits<double>::infinity();
  for (const SourceTurning& s : a.sources) t = std::min(t, s.from_s);
  return t;
}

}  // namespace

nlohmann::ordered_json agreementJson(const SensorAgreement& a, const std::string& wheels_from) {
  nlohmann::ordered_json sources = nlohmann::ordered_json::object();
  for (const SourceTurning& t : a.sources) {
    nlohmann::ordered_json j = {{"from_s", t.from_s},
                                {"to_s", t.to_s},
                                {"net_deg", t.net_rad * kDeg},
                                {"absolute_deg", t.absolute_rad * kDeg}};
    if (t.name == "wheels") j["encoders_from"] = wheels_from;
    sources[t.name] = j;
  }
  nlohmann::ordered_json pairs = nlohmann::ordered_json::array();
  for (const PairAgreement& p : a.pairs) pairs.push_back(pairJson(p));
  return {{"window_s", a.params.window_s},
          {"step_s", a.params.step_s},
          {"disagreement_sigmas", a.params.disagreement_sigmas},
          {"disagreement_floor_deg", a.params.disagreement_floor_rad * kDeg},
          {"turning_from_s", a.shared_from_s},
          {"turning_to_s", a.shared_to_s},
          {"sources", sources},
          {"pairs", pairs},
          {"findings", a.findings}};
}

std::string agreementText(const SensorAgreement& a) {
  if (a.sources.size() < 2) return "sensor agreement: fewer than two rotation sources\n";
  const double t_start = startOf(a);
  std::string s =
      line("sensor agreement (%.0f s windows):\n  turning over +%.1f..+%.1f s (what all cover):",
           a.params.window_s, a.shared_from_s - t_start, a.shared_to_s - t_start);
  for (std::size_t i = 0; i < a.sources.size(); ++i)
    s += line("%s %s net %.1f deg, absolute %.1f deg", i ? ";" : "", a.sources[i].name.c_str(),
              a.sources[i].net_rad * kDeg, a.sources[i].absolute_rad * kDeg);
  s += "\n";
  for (const PairAgreement& p : a.pairs) s += pairText(p, t_start);
  for (const std::string& f : a.findings) s += "  finding: " + f + "\n";
  return s;
}

std::string wheelsGyroConflictText(const SensorAgreement& a) {
  const PairAgreement* p = a.wheelsGyroConflict();
  if (!p) return "";
  return line(
             "the wheels and the gyro disagree beyond what any wheel geometry explains "
             "in %zu span%s:",
             p->disagreements.size(), p->disagreements.size() == 1 ? "" : "s") +
         spansText(a, *p);
}

std::string spansText(const SensorAgreement& a, const PairAgreement& p) {
  std::string s;
  for (const Disagreement& d : p.disagreements)
    s += line(" +%.1f..+%.1f s from the start (%s);", d.t0_s - startOf(a), d.t1_s - startOf(a),
              d.likely_cause.c_str());
  return s;
}

}  // namespace slamprep::algo
