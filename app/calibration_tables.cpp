#include "slamprep/app/calibration_tables.hpp"

#include <cmath>
#include <cstdio>
#include <iomanip>
#include <iostream>
#include <limits>
#include <numbers>
#include <sstream>

#include "slamprep/algo/calibration/calibration_json.hpp"

namespace slamprep::app {
namespace {

// Lengths in mm, the yaw in degrees: what a person reads.
std::string human(double value, int i) {
  std::ostringstream s;
  s << std::fixed;
  if (i == 5)
    s << std::setprecision(3) << value * 180.0 / std::numbers::pi << " deg";
  else
    s << std::setprecision(3) << value * 1000.0 << " mm";
  return s.str();
}

// "101.234 +- 0.012 mm" (no sigma: the value alone).
std::string withSigma(const algo::CalibrationResult& r, int i) {
  const Eigen::VectorXd v = algo::calibrationValues(r);
  if (r.covariance.size() == 0) return human(v(i), i);
  const std::string value = human(v(i), i);
  const std::string sigma = human(r.sigma()(i), i);
  return value.substr(0, value.rfind(' ')) + " +- " + sigma;
}

void printCompactRuns(const std::vector<algo::MethodReport>& methods) {
  for (const algo::MethodReport& m : methods) {
    const algo::CalibrationResult& r = m.run.result;
    std::cout << "  " << std::left << std::setw(9) << algo::calibrationMethodName(m.run.method);
    if (!r.ok) {
      std::cout << "REFUSED: " << r.reason << "\n";
      continue;
    }
    const int n = r.estimates_mount ? 6 : 3;
    for (int i = 0; i < n; ++i)
      std::cout << (i ? ", " : "") << algo::kCalibrationKeys[i] << " " << withSigma(r, i);
    std::cout << "\n";
  }
}

// Eq. (3) of combine_recordings.hpp: the rotation per wheel angle, r / b, over the recordings.
void printRatioRows(const algo::CombinedRun& c) {
  const Eigen::VectorXd v = algo::calibrationValues(c.run.result);
  for (int wheel = 0; wheel < 2; ++wheel) {
    const double chi2 = c.estimate.ratio_chi2_dof(wheel);
    if (!std::isfinite(chi2)) continue;
    const double sigma = std::sqrt(algo::wheelRatioVariance(v, c.run.result.covariance, wheel));
    std::ostringstream q, s;
    q << std::fixed << std::setprecision(5) << v(wheel) / v(2);
    s << std::fixed << std::setprecision(5) << sigma;
    std::cout << "  " << std::setw(10) << (wheel == 0 ? "r_L/b" : "r_R/b") << std::setw(16)
              << q.str() << std::setw(24) << s.str() << std::fixed << std::setprecision(2) << chi2
              << std::defaultfloat << "\n";
  }
}

void printCombinedMethod(const algo::CombinedRun& c, const eval::RecordingsCalibration& r) {
  const algo::CalibrationResult& res = c.run.result;
  std::cout << "\n" << algo::calibrationMethodName(c.run.method) << ": ";
  if (!res.ok) {
    std::cout << "REFUSED: " << res.reason << "\n";
    return;
  }
  std::cout << c.recordings.size() << " of " << r.recordings.size() << " recordings\n";
  std::cout << "  " << std::left << std::setw(10) << "param" << std::setw(16) << "estimate"
            << std::setw(24) << "1-sigma"
            << "chi2/dof\n";
  const Eigen::VectorXd v = algo::calibrationValues(res), s = res.sigma();
  const Eigen::VectorXd& chi2 = c.estimate.chi2_dof;
  for (int i = 0; i < v.size(); ++i) {
    std::ostringstream sigma, x2;
    sigma << human(s(i), i);
    if (c.estimate.sigma_scale(i) > 1.0)
      sigma << " (x" << std::fixed << std::setprecision(2) << c.estimate.sigma_scale(i) << ")";
    if (std::isfinite(chi2(i)))
      x2 << std::fixed << std::setprecision(2) << chi2(i);
    else
      x2 << "-";
    std::cout << "  " << std::setw(10) << algo::kCalibrationKeys[i] << std::setw(16)
              << human(v(i), i) << std::setw(24) << sigma.str() << x2.str() << "\n";
  }
  printRatioRows(c);
}

// The wheel parameters whose combined value lies outside the range of the recordings' values
// by more than 0.1 % of it (a hair outside is the weighting's rounding, not a disagreement), as
// ", outside the recordings' range: r_L 25.040 mm (30.059 mm to 33.241 mm)"; "" when none.
std::string outsideRecordings(const algo::CombinedRun& c, const eval::RecordingsCalibration& r) {
  const Eigen::VectorXd combined = algo::calibrationValues(c.run.result);
  std::ostringstream out;
  for (int j = 0; j < 3; ++j) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const int rec : c.recordings)
      for (const algo::CalibrationRun& run : r.recordings[rec].calibration.runs)
        if (run.method == c.run.method && run.result.ok) {
          lo = std::min(lo, algo::calibrationValues(run.result)(j));
          hi = std::max(hi, algo::calibrationValues(run.result)(j));
        }
    const double margin = 1e-3 * std::max(std::abs(lo), std::abs(hi));
    if (!(combined(j) < lo - margin || combined(j) > hi + margin)) continue;
    out << (out.tellp() == 0 ? ", outside the recordings' range: " : ", ")
        << algo::kCalibrationKeys[j] << " " << human(combined(j), j) << " (" << human(lo, j)
        << " to " << human(hi, j) << ")";
  }
  return out.str();
}

// The warning for a method whose recordings disagree on r / b (Eq. 3), what drives pin down best.
void warnRatioInconsistent(const algo::CombinedRun& c, const eval::RecordingsCalibration& r) {
  const Eigen::Vector2d& chi2 = c.estimate.ratio_chi2_dof;
  const int wheel = chi2(1) > chi2(0) ? 1 : 0;
  if (!c.run.result.ok || !(chi2(wheel) > algo::CombineParams{}.max_chi2_dof)) return;
  std::cout << "WARNING: " << algo::calibrationMethodName(c.run.method)
            << ": the recordings disagree on how far the robot turns per wheel turn ("
            << (wheel == 0 ? "r_L/b" : "r_R/b") << ", chi2/dof " << std::fixed
            << std::setprecision(2) << chi2(wheel) << std::defaultfloat
            << "), which a drive pins down better than r or b alone: another floor, load or "
               "robot, slip in turns, or the scans' rotation; the combined r and b keep the "
               "weighted ratio"
            << outsideRecordings(c, r) << "\n";
}

// The warning for a method whose recordings disagree beyond their sigmas, naming the worst
// recording and parameter.
void warnInconsistent(const algo::CombinedRun& c, const eval::RecordingsCalibration& r) {
  const algo::CombinedEstimate& e = c.estimate;
  if (!c.run.result.ok || e.worst_input < 0) return;
  const int j = e.worst_parameter;
  const int rec = c.recordings[e.worst_input];
  const algo::CalibrationResult* worst = nullptr;
  for (const algo::CalibrationRun& run : r.recordings[rec].calibration.runs)
    if (run.method == c.run.method) worst = &run.result;
  const double x = algo::calibrationValues(*worst)(j);
  const double combined = algo::calibrationValues(c.run.result)(j);
  std::cout << "WARNING: " << algo::calibrationMethodName(c.run.method)
            << ": the recordings disagree beyond their sigmas (chi2/dof " << std::fixed
            << std::setprecision(2) << e.chi2_dof(j) << " on " << algo::kCalibrationKeys[j]
            << "); the combined sigma of each such parameter is scaled by sqrt(chi2/dof). Worst: "
            << "recording " << rec + 1 << " (" << r.recordings[rec].dataset << "), "
            << algo::kCalibrationKeys[j] << " " << human(x, j) << " against the combined "
            << human(combined, j) << ", " << std::setprecision(1)
            << std::abs(x - combined) / worst->sigma()(j) << " of its sigmas\n"
            << std::defaultfloat;
}

// What the recording's mount did as a prior (algo/calibration/mount_prior.hpp), one line.
void printMountPrior(const algo::MountPriorUse& u) {
  const Eigen::VectorXd& v = u.without_prior;
  std::cout << "  mount prior: " << u.prior.from << " (1-sigma " << std::fixed
            << std::setprecision(0) << u.prior.sigma_xy_m * 1e3 << " mm, " << std::setprecision(1)
            << u.prior.sigma_yaw_rad * 180.0 / std::numbers::pi << " deg), chi2 "
            << std::setprecision(1) << u.chi2;
  if (u.applied)
    std::cout << ": fused; the fit alone had b " << human(v(2), 2) << ", lidar x " << human(v(3), 3)
              << ", y " << human(v(4), 4) << "\n";
  else
    std::cout << " > " << u.prior.max_chi2
              << ": not fused, the fit contradicts it (see the lidar_mount flag)\n";
  std::cout << std::defaultfloat;
}

// The sigmas the sandwich raised by at least 5 %: where the intervals' residuals differ in size
// (slip in turns, long intervals) the model-based sigmas understated them.
void printSandwichFactors(const algo::CalibrationResult& r) {
  std::ostringstream raised;
  for (std::size_t i = 0; i < r.sigma_sandwich_factors.size(); ++i)
    if (r.sigma_sandwich_factors[i] >= 1.05)
      raised << (raised.tellp() == 0 ? "" : ", ") << algo::kCalibrationKeys[i] << " x" << std::fixed
             << std::setprecision(2) << r.sigma_sandwich_factors[i];
  if (raised.tellp() > 0)
    std::cout << "  sigmas raised to the sandwich's (residuals that differ between intervals): "
              << raised.str() << "\n";
}

}  // namespace

void printTable(const std::vector<algo::CalibrationRun>& rows,
                const std::optional<algo::CalibrationTruth>& truth_of) {
  std::optional<Eigen::VectorXd> truth;
  if (truth_of) truth = truth_of->values();
  for (const algo::CalibrationRun& row : rows) {
    const auto& r = row.result;
    std::cout << "\n" << algo::calibrationMethodName(row.method) << ": ";
    if (!r.ok) {
      std::cout << "REFUSED: " << r.reason << "\n";
      continue;
    }
    std::cout << r.intervals_used << " intervals/runs, condition number " << std::setprecision(3)
              << r.condition_number << ", " << r.intervals_trimmed << " trimmed\n";
    if (r.rotation_heteroscedasticity > algo::kTurnHeteroscedasticityMinStatistic)
      std::cout << "  rotation residuals grow with the turn (slip in turns; Breusch-Pagan "
                << std::fixed << std::setprecision(1) << r.rotation_heteroscedasticity << " > "
                << algo::kTurnHeteroscedasticityMinStatistic << ")\n"
                << std::defaultfloat;
    printSandwichFactors(r);
    for (const algo::TrimmedInterval& t : r.trimmed_worst)
      std::cout << "  trimmed " << std::fixed << std::setprecision(3) << t.t0_s << ".." << t.t1_s
                << " s: " << t.reason << " (" << std::setprecision(1) << t.residual_sigmas
                << " robust sigmas)\n"
                << std::defaultfloat;
    std::cout << "  " << std::left << std::setw(10) << "param" << std::setw(16) << "estimate"
              << std::setw(16) << "1-sigma";
    if (truth)
      std::cout << std::setw(16) << "truth" << std::setw(14) << "error"
                << "error %";
    std::cout << "\n";
    const Eigen::VectorXd v = algo::calibrationValues(r), s = r.sigma();
    for (int i = 0; i < v.size(); ++i) {
      std::cout << "  " << std::setw(10) << algo::kCalibrationKeys[i] << std::setw(16)
                << human(v(i), i) << std::setw(16)
                << (r.covariance.size() > 0 ? human(s(i), i) : "n/a");
      if (truth) {
        const double e = algo::calibrationError(v, *truth, i);
        std::ostringstream pct;
        if (std::abs((*truth)(i)) > 1e-12)
          pct << std::fixed << std::setprecision(4) << 100.0 * e / std::abs((*truth)(i)) << " %";
        else
          pct << "-";
        std::cout << std::setw(16) << human((*truth)(i), i) << std::setw(14) << human(e, i)
                  << pct.str();
      }
      std::cout << "\n";
    }
    if (row.mount_prior) printMountPrior(*row.mount_prior);
  }
}

void printRecordings(const eval::RecordingsCalibration& r) {
  for (std::size_t i = 0; i < r.recordings.size(); ++i) {
    const eval::DatasetCalibration& c = r.recordings[i].calibration;
    std::cout << "\nrecording " << i + 1 << ": " << r.recordings[i].dataset << " ("
              << c.intervals.intervals.size() << " intervals)\n";
    printCompactRuns(r.report.recordings[i].methods);
  }
  std::cout << "\ncombined over " << r.recordings.size()
            << " recordings (information-weighted; where chi2/dof > 2 the sigma is scaled by "
               "sqrt(chi2/dof), marked xN):\n";
  for (const algo::CombinedRun& c : r.combined) printCombinedMethod(c, r);
  std::cout << "\n";
  for (const algo::CombinedRun& c : r.combined) {
    warnInconsistent(c, r);
    warnRatioInconsistent(c, r);
  }
}

namespace {

// What a flag's ratio is a ratio of, as printed after it; nullptr for a flag without a ratio.
const char* ratioMeaning(const std::string& param) {
  if (param == "b_vs_gyro") return " (b over the gyro's b): ";
  if (param == "held_out") return " (held-out error, calibrated over raw): ";
  if (param == "range_scale") return " x nominal (r_L, r_R and b by one factor): ";
  if (param == "b_not_measured" || param == "wheels_vs_scans" || param == "lidar_mount")
    return nullptr;
  return " x nominal (more than 15 % off): likely cause: ";
}

}  // namespace

void printFlags(const std::vector<algo::MethodReport>& methods, const std::string& label) {
  for (const algo::MethodReport& m : methods)
    for (const algo::NominalFlag& f : m.flags) {
      std::cout << "FLAG " << label << algo::calibrationMethodName(m.run.method) << ": " << f.param;
      if (const char* meaning = ratioMeaning(f.param))
        std::cout << " = " << std::fixed << std::setprecision(3) << f.ratio << meaning
                  << std::defaultfloat;
      else
        std::cout << ": ";
      std::cout << f.likely_cause << "\n";
    }
}

void printAgainstNominal(const std::vector<algo::MethodReport>& methods, const std::string& label,
                         const std::string& data) {
  for (const algo::MethodReport& m : methods) {
    const auto& t = m.against_nominal;
    if (!t) continue;
    char line[320];
    std::snprintf(line, sizeof line,
                  "against the nominal %s%s: r_L %+.1f, r_R %+.1f, b %+.1f sigma; chi2 %.1f over "
                  "3, p %.2g: %s\n",
                  label.c_str(), std::string(algo::calibrationMethodName(m.run.method)).c_str(),
                  t->z(0), t->z(1), t->z(2), t->chi2, t->p,
                  t->shows_nominal_wrong
                      ? (data + " the nominal geometry wrong").c_str()
                      : "not shown wrong at p < 0.001, the three together (the calibration "
                        "moves the odometry within its own uncertainty: keep the nominal unless "
                        "more recordings say otherwise)");
    std::cout << line;
  }
}

void printValidation(const std::vector<algo::MethodReport>& methods, const std::string& label) {
  bool header = false;
  for (const algo::MethodReport& m : methods) {
    if (!m.validation) continue;
    const algo::ValidationFigures& v = *m.validation;
    if (!header) {
      // The stream's precision is whatever the last table left; the percentage is whole.
      std::cout << "\nheld-out validation " << label << "(last " << std::lround(v.fraction * 100.0)
                << " % of the scans; relative pose error over 10 s windows against scan-to-map "
                   "matching):\n  "
                << std::left << std::setw(10) << "method" << std::setw(14) << "raw m"
                << std::setw(14) << "raw deg" << std::setw(16) << "calibrated m"
                << "calibrated deg\n";
      header = true;
    }
    std::cout << "  " << std::setw(10) << algo::calibrationMethodName(m.run.method) << std::fixed
              << std::setprecision(4) << std::setw(14) << v.raw.trans_m << std::setw(14)
              << v.raw.rot_deg << std::setw(16) << v.calibrated.trans_m << v.calibrated.rot_deg
              << std::defaultfloat;
    if (v.calibrated.trans_m > v.raw.trans_m)
      std::cout << "  calibrated WORSE than raw in translation";
    if (v.calibrated.rot_deg > v.raw.rot_deg)
      std::cout << "  calibrated WORSE than raw in rotation";
    std::cout << "\n";
    if (const auto& w = v.calibrated_wheels)  // the odometry alone, apart from the mount
      std::cout << "  " << std::setw(10) << ""
                << "calibrated wheels, dataset's mount: " << std::fixed << std::setprecision(4)
                << w->trans_m << " m, " << w->rot_deg << " deg\n"
                << std::defaultfloat;
  }
}

namespace {

void printLeaveOneOutRow(const algo::LeaveOneOutScore& s, std::size_t index) {
  std::cout << "  " << std::left << std::setw(6) << index << std::setw(8) << s.others;
  if (!s.figures) {
    std::cout << s.note << "\n";
    return;
  }
  const algo::ValidationFigures& v = *s.figures;
  std::cout << std::fixed << std::setprecision(4) << std::setw(14) << v.raw.trans_m << std::setw(14)
            << v.raw.rot_deg << std::setw(16) << v.calibrated.trans_m << std::setw(16)
            << v.calibrated.rot_deg << std::defaultfloat;
  if (v.calibrated.trans_m > v.raw.trans_m) std::cout << "WORSE in translation  ";
  if (v.calibrated.rot_deg > v.raw.rot_deg) std::cout << "WORSE in rotation";
  std::cout << "\n";
}

}  // namespace

void printLeaveOneOut(const std::vector<algo::LeaveOneOutMethod>& methods) {
  for (const algo::LeaveOneOutMethod& m : methods) {
    std::cout << "\nleave one recording out, " << algo::calibrationMethodName(m.method)
              << " (each recording whole, with the other recordings' combined estimate; relative "
                 "pose error over 10 s windows against scan-to-map matching):\n  "
              << std::left << std::setw(6) << "rec." << std::setw(8) << "others" << std::setw(14)
              << "raw m" << std::setw(14) << "raw deg" << std::setw(16) << "calibrated m"
              << std::setw(16) << "calibrated deg"
              << "\n";
    for (std::size_t i = 0; i < m.recordings.size(); ++i)
      printLeaveOneOutRow(m.recordings[i], i + 1);
    const algo::BeatsRaw b = algo::beatsRaw(m);
    std::cout << "  calibrated beats raw on " << b.trans << " of " << b.scored
              << " recordings in translation, " << b.rot << " of " << b.scored << " in rotation\n";
  }
}

}  // namespace slamprep::app
