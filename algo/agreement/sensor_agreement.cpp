#include "slamprep/algo/agreement/sensor_agreement.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <sstream>

#include "slamprep/core/order_statistics.hpp"

namespace slamprep::algo {
namespace {

constexpr double kDeg = 180.0 / std::numbers::pi;

/// One window's equation of Eq. 1 or Eq. 2: y = x^T p.
struct Row {
  double t0_s, t1_s;
  double y;
  Eigen::VectorXd x;
  double turn_a, turn_b;  ///< what the two sources turned (wheels: with the nominal geometry)
};

/// A named rotation source: its heading in pieces (what a source says across a break between
/// two pieces is unknown), and the wheel angles where it is the wheels.
struct Source {
  std::string name;
  std::vector<HeadingSeries> pieces;
  const WheelTrack* wheels = nullptr;
  bool is_gyro = false;
  const TimeSeries<double>* travel = nullptr;  ///< the odometry topic's signed travel
  /// Poses and wheel angles keep what they turned across a gap between samples; rates do not.
  double gapLimit(double max_gap_s) const {
    return is_gyro ? max_gap_s : std::numeric_limits<double>::infinity();
  }

  double from() const { return pieces.front().frontStamp(); }
  double to() const { return pieces.back().backStamp(); }
  std::optional<double> turn(double t0, double t1, double max_gap_s) const {
    for (const HeadingSeries& h : pieces)
      if (h.covers(t0) && h.covers(t1)) return turned(h, t0, t1, gapLimit(max_gap_s));
    return std::nullopt;
  }
};

/// The columns of a pair's equation: Eq. 1's (a, c) or Eq. 2's s, then g and k where they apply.
struct Columns {
  bool bias = false;              ///< g: one source is the gyro
  const Source* mover = nullptr;  ///< k: Eq. 2 with the odometry topic, whose travel it is
  Eigen::Index size() const { return 2 + (bias ? 1 : 0) + (mover ? 1 : 0); }
  Eigen::Index travelIndex() const { return bias ? 3 : 2; }
};

Columns columnsOf(const Source& a, const Source& b) {
  Columns c;
  c.bias = a.is_gyro || b.is_gyro;
  if (!a.wheels) c.mover = a.travel ? &a : (b.travel ? &b : nullptr);
  return c;
}

/// The equation of one window [t0, t1] (Eq. 1 where a is the wheels, else Eq. 2); nullopt where
/// a source does not cover it.
std::optional<Row> rowAt(const Source& a, const Source& b, double t0, double t1, double lag_s,
                         const AgreementParams& p) {
  const auto da = a.turn(t0, t1, p.max_gap_s);
  const auto db = b.turn(t0 + lag_s, t1 + lag_s, p.max_gap_s);
  if (!da || !db) return std::nullopt;
  const Columns c = columnsOf(a, b);
  Eigen::VectorXd x(c.size());
  if (a.wheels) {
    const auto dphi = turned(a.wheels->phi_rad, t0, t1, a.gapLimit(p.max_gap_s));
    if (!dphi) return std::nullopt;
    x.head<2>() << (*dphi)(1), -(*dphi)(0);  // Eq. 1: a dphi_R - c dphi_L
  } else {
    x.head<2>() << *da, 0.0;  // Eq. 2: s dA (the second column stays unused)
  }
  if (c.bias) x(2) = t1 - t0;
  if (c.mover) {
    const double shift = c.mover == &b ? lag_s : 0.0;
    const auto ds =
        turned(*c.mover->travel, t0 + shift, t1 + shift, c.mover->gapLimit(p.max_gap_s));
    if (!ds) return std::nullopt;
    x(c.travelIndex()) = *ds;
  }
  return Row{t0, t1, *db, x, *da, *db};
}

/// The rows of the pair (a, b) over every window both cover, b read `lag_s` later.
std::vector<Row> rowsOf(const Source& a, const Source& b, double lag_s, const AgreementParams& p) {
  std::vector<Row> rows;
  const double from = std::max(a.from(), b.from() - lag_s);
  const double to = std::min(a.to(), b.to() - lag_s);
  const auto n = static_cast<long>(std::floor((to - from - p.window_s) / p.step_s + 1e-9));
  for (long i = 0; i <= n; ++i) {
    const double t0 = from + double(i) * p.step_s;
    if (auto row = rowAt(a, b, t0, t0 + p.window_s, lag_s, p)) rows.push_back(std::move(*row));
  }
  return rows;
}

struct Fit {
  Eigen::VectorXd coef;
  std::vector<double> residual;
  std::vector<bool> kept;
  double sigma = 0.0;
};

/// Weighted least squares; a zero weight leaves a window out.
Eigen::VectorXd solve(const std::vector<Row>& rows, const std::vector<double>& weight) {
  const Eigen::Index n = rows.front().x.size();
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(n, n);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n);
  // Element by element, as Eigen's (w x) x^T and (w x) y evaluate, without their temporaries.
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const Eigen::VectorXd& x = rows[i].x;
    for (Eigen::Index j = 0; j < n; ++j) {
      const double wx = weight[i] * x(j);
      for (Eigen::Index k = 0; k < n; ++k) A(j, k) += wx * x(k);
      rhs(j) += wx * rows[i].y;
    }
  }
  // Minimum-norm solution: straight driving leaves a + c undetermined, an unused column all.
  return A.completeOrthogonalDecomposition().solve(rhs);
}

std::vector<double> residuals(const std::vector<Row>& rows, const Eigen::VectorXd& coef) {
  std::vector<double> r(rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) r[i] = rows[i].y - rows[i].x.dot(coef);
  return r;
}

/// The least-absolute-deviations fit (IRLS, weights 1 / |r|): a start that a block of faulty
/// windows cannot drag, as it drags least squares.
Eigen::VectorXd leastAbsolute(const std::vector<Row>& rows, double floor) {
  std::vector<double> weight(rows.size(), 1.0);
  Eigen::VectorXd coef = solve(rows, weight);
  for (int round = 0; round < 50; ++round) {
    const std::vector<double> r = residuals(rows, coef);
    for (std::size_t i = 0; i < rows.size(); ++i) weight[i] = 1.0 / std::max(std::abs(r[i]), floor);
    coef = solve(rows, weight);
  }
  return coef;
}

/// From the least-absolute-deviations start: the windows beyond outlier_sigmas robust sigmas
/// (MAD over all windows, so the faults cannot inflate the scale that judges them) dropped and
/// least squares on the rest, repeated until the kept set repeats.
Fit robustFit(const std::vector<Row>& rows, const AgreementParams& p) {
  Fit f;
  f.coef = leastAbsolute(rows, p.min_sigma_rad);
  for (int round = 0; round < 20; ++round) {
    f.residual = residuals(rows, f.coef);
    std::vector<double> abs_r(rows.size());
    for (std::size_t i = 0; i < rows.size(); ++i) abs_r[i] = std::abs(f.residual[i]);
    f.sigma = std::max(1.4826 * median(abs_r), p.min_sigma_rad);
    std::vector<bool> kept(rows.size());
    for (std::size_t i = 0; i < rows.size(); ++i) kept[i] = abs_r[i] <= p.outlier_sigmas * f.sigma;
    if (kept == f.kept) break;
    f.kept = kept;
    f.coef = solve(rows, std::vector<double>(kept.begin(), kept.end()));
  }
  return f;
}

std::string fmtDeg(double rad) {
  std::ostringstream s;
  s.precision(1);
  s << std::fixed << rad * kDeg;
  return s.str();
}

/// Why `a` turned `turn_a` where its model from `b` expects `b` to turn `turn_b`.
std::string likelyCause(const Source& a, const Source& b, double predicted_b, double turn_b) {
  const bool plural = a.name == "wheels" || a.name == "scans";
  const std::string told = a.name + (plural ? " say " : " says ") + fmtDeg(predicted_b) +
                           " deg where " + b.name + " turned " + fmtDeg(turn_b) + " deg: ";
  if (!a.wheels)
    return told + (b.name == "scans" || a.name == "scans"
                       ? "a failed scan match, or the other sensor's fault"
                       : "one of the two is wrong here (a gyro fault, or an odometry glitch)");
  // A hold of a few seconds fills only part of a 5 s window: the robot turning less than half
  // of what its wheels say is a hold, not the few-percent shortfall of slip.
  const bool held = std::abs(turn_b) < 0.5 * std::abs(predicted_b);
  const bool opposite = turn_b * predicted_b < 0.0;
  if (held || opposite)
    return told + "the robot was lifted or blocked while its wheels turned (or they slipped badly)";
  if (std::abs(turn_b) > std::abs(predicted_b))
    return told + "the robot turned more than its wheels: pushed, or a wheel spun freely";
  return told + "the wheels turned more than the robot: wheel slip";
}

/// A span whose turns agree as a whole but not window by window: the two disagree on when.
std::string transientCause(const Source& a, const Source& b, double predicted_b, double turn_b) {
  return a.name + (a.name == "wheels" || a.name == "scans" ? " say " : " says ") +
         fmtDeg(predicted_b) + " deg and " + b.name + " turned " + fmtDeg(turn_b) +
         " deg over the span, but not at the same times inside it: a varying delay between "
         "them, or a turn one of them saw late (a slipping or blocked wheel that caught up)";
}

/// The flagged windows merged into spans, each with what the sources turned over it.
std::vector<Disagreement> disagreements(const Source& a, const Source& b,
                                        const std::vector<Row>& rows, const Fit& f, double lag_s,
                                        const AgreementParams& p) {
  const double limit = std::max(p.disagreement_sigmas * f.sigma, p.disagreement_floor_rad);
  std::vector<Disagreement> spans;
  std::vector<std::size_t> worst;  // per span: its worst window, whose turns name the cause
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const double r = std::abs(f.residual[i]);
    if (r <= limit) continue;
    if (spans.empty() || rows[i].t0_s > spans.back().t1_s) {
      spans.push_back({rows[i].t0_s, rows[i].t1_s, 0.0, 0.0, r, ""});
      worst.push_back(i);
    }
    spans.back().t1_s = rows[i].t1_s;
    if (r >= spans.back().max_residual_rad) {
      spans.back().max_residual_rad = r;
      worst.back() = i;
    }
  }
  for (std::size_t k = 0; k < spans.size(); ++k) {
    Disagreement& d = spans[k];
    const Row& w = rows[worst[k]];
    const auto whole = rowAt(a, b, d.t0_s, d.t1_s, lag_s, p);
    if (!whole) continue;
    d.turn_a_rad = whole->turn_a;
    d.turn_b_rad = whole->turn_b;
    // Over a span whose turns agree, the windows disagreed on when; otherwise the worst window
    // (not the span, which the windows around it dilute) tells what happened.
    const double predicted = whole->x.dot(f.coef);
    d.likely_cause = std::abs(predicted - whole->turn_b) < p.disagreement_floor_rad
                         ? transientCause(a, b, predicted, whole->turn_b)
                         : likelyCause(a, b, w.x.dot(f.coef), w.turn_b);
  }
  return spans;
}

/// RMS of the residuals, each capped at `cap`: how well a fit explains the windows. A window a
/// wrong delay puts beyond the cap still counts, at the cap: dropped instead (the 80 % of the
/// windows that fit best, until 2026-11-28), the few windows whose turn rate changes, the only
/// ones that show a delay, left every delay scoring the same on a clean drive. Not the MAD,
/// which a wrong delay on a periodic drive can keep small by fitting just over half of them.
double cappedRms(const Fit& f, double cap) {
  double sum = 0.0;
  for (double r : f.residual) sum += std::min(r * r, cap * cap);
  return std::sqrt(sum / double(std::max<std::size_t>(1, f.residual.size())));
}

/// Where, within +-0.5 of grid point k, the parabola through the scores at k-1, k, k+1 is
/// lowest: the grid's step no longer bounds the delay's resolution.
double parabolaVertex(const std::vector<double>& s, std::size_t k) {
  if (k == 0 || k + 1 >= s.size()) return 0.0;
  const double curve = s[k - 1] - 2.0 * s[k] + s[k + 1];
  if (!(curve > 0.0) || !std::isfinite(curve)) return 0.0;
  return std::clamp(0.5 * (s[k - 1] - s[k + 1]) / curve, -0.5, 0.5);
}

/// Whether a delay whose capped RMS is `with` against `without` at none is kept: by its gain, or
/// by the likelihood ratio of Gaussian residuals over independent windows (AgreementParams).
bool lagShows(double without, double with, std::size_t windows, const AgreementParams& p) {
  if (!(with < without)) return false;
  if (with < p.lag_gain * without) return true;
  const double independent = double(windows) * p.step_s / p.window_s;
  return independent * std::log(without * without / (with * with)) > p.lag_significance;
}

/// The delay of b's clock behind a's over a grid of +-max_lag_s: the one whose fit explains the
/// windows best (cappedRms, one cap for every delay: outlier_sigmas robust sigmas of the best
/// fit, found from the fit without delay and again from the best until it repeats; each fit's
/// own sigma rewarded a delay that fits half the windows exactly, the fit without delay's alone
/// let a real robot's lifted windows outweigh the rest), refined between grid points by a
/// parabola, kept only where it beats no delay by lag_gain or by lag_significance (a delay the data
/// cannot show is none).
double bestLag(const Source& a, const Source& b, const AgreementParams& p) {
  const auto steps = static_cast<std::size_t>(std::round(p.max_lag_s / p.lag_step_s));
  std::vector<std::optional<Fit>> fits;
  for (std::size_t k = 0; k <= 2 * steps; ++k) {
    const double lag = (double(k) - double(steps)) * p.lag_step_s;
    const std::vector<Row> rows = rowsOf(a, b, lag, p);
    fits.push_back(rows.size() < 3 ? std::nullopt : std::optional<Fit>(robustFit(rows, p)));
  }
  if (!fits[steps]) return 0.0;
  std::vector<double> scores(fits.size());
  std::size_t best = steps;
  for (int pass = 0; pass < 5; ++pass) {
    const double cap = p.outlier_sigmas * fits[best]->sigma;
    for (std::size_t k = 0; k < fits.size(); ++k)
      scores[k] = fits[k] ? cappedRms(*fits[k], cap) : std::numeric_limits<double>::infinity();
    const auto next =
        static_cast<std::size_t>(std::min_element(scores.begin(), scores.end()) - scores.begin());
    if (next == best) break;
    best = next;
  }
  if (!lagShows(scores[steps], scores[best], fits[steps]->residual.size(), p)) return 0.0;
  return (double(best) - double(steps) + parabolaVertex(scores, best)) * p.lag_step_s;
}

PairAgreement comparePair(const Source& a, const Source& b, const AgreementParams& p) {
  PairAgreement out;
  out.a = a.name;
  out.b = b.name;
  out.model = a.wheels ? "wheels" : "scale";
  out.lag_s = p.max_lag_s > 0.0 ? bestLag(a, b, p) : 0.0;
  const std::vector<Row> rows = rowsOf(a, b, out.lag_s, p);
  out.windows = rows.size();
  if (rows.empty()) return out;
  const Fit f = robustFit(rows, p);
  double sum_a = 0.0, sum_b = 0.0, sum_sq = 0.0;
  for (std::size_t i = 0; i < rows.size(); ++i)
    if (f.kept[i]) {
      ++out.kept;
      sum_a += std::abs(rows[i].turn_a);
      sum_b += std::abs(rows[i].turn_b);
      sum_sq += f.residual[i] * f.residual[i];
    }
  out.scale = sum_b > 0.0 ? sum_a / sum_b : 1.0;
  out.rms_residual_rad = out.kept ? std::sqrt(sum_sq / double(out.kept)) : 0.0;
  out.sigma_rad = f.sigma;
  const Columns c = columnsOf(a, b);
  if (c.bias) out.bias_radps = f.coef(2);
  if (c.mover) out.travel_rad_per_m = f.coef(c.travelIndex());
  if (a.wheels) {
    out.wheel_ratios = Eigen::Vector2d(f.coef(0), f.coef(1));
    const DiffDriveParams& g = a.wheels->nominal;
    if (f.coef(0) + f.coef(1) > 0.0)
      out.effective_wheel_base_m = (g.radius_left_m + g.radius_right_m) / (f.coef(0) + f.coef(1));
  }
  out.disagreements = disagreements(a, b, rows, f, out.lag_s, p);
  return out;
}

/// What `s` turned from `from` to `to`: the span every source covers, so that the sources'
/// figures compare (an odometry that starts before the lidar, or scans cut for validation, would
/// otherwise add turns the others never saw).
SourceTurning turningOf(const Source& s, double from, double to, const AgreementParams& p) {
  SourceTurning t{s.name, s.from(), s.to(), 0.0, 0.0};
  const double no_gap_limit = std::numeric_limits<double>::infinity();
  for (const HeadingSeries& h : s.pieces) {
    const double a = std::max(from, h.frontStamp()), b = std::min(to, h.backStamp());
    if (!(a < b)) continue;
    t.net_rad += turned(h, a, b, no_gap_limit).value_or(0.0);
    for (double t0 = a; t0 < b; t0 += p.step_s)
      if (const auto d = turned(h, t0, std::min(t0 + p.step_s, b), s.gapLimit(p.max_gap_s)))
        t.absolute_rad += std::abs(*d);
  }
  return t;
}

std::vector<HeadingSeries> usable(std::vector<HeadingSeries> pieces) {
  std::erase_if(pieces, [](const HeadingSeries& h) { return h.size() < 2; });
  return pieces;
}

std::vector<Source> namedSources(const RotationSources& in) {
  std::vector<Source> out;
  auto add = [&](const char* name, std::vector<HeadingSeries> pieces, const WheelTrack* wheels,
                 bool gyro, const TimeSeries<double>* travel = nullptr) {
    pieces = usable(std::move(pieces));
    if (!pieces.empty()) out.push_back({name, std::move(pieces), wheels, gyro, travel});
  };
  if (in.wheels) add("wheels", {wheelHeading(*in.wheels, in.wheels->nominal)}, &*in.wheels, false);
  if (in.gyro) add("gyro", {*in.gyro}, nullptr, true);
  const bool travels = in.odometry_travel && in.odometry_travel->size() >= 2;
  if (in.odometry)
    add("odometry", {*in.odometry}, nullptr, false, travels ? &*in.odometry_travel : nullptr);
  add("scans", in.scans, nullptr, false);
  return out;
}

/// "3.8 % more" or "3.8 % less": a ratio as words, never "-3.8 % more".
std::string fmtMoreOrLess(double ratio) {
  std::ostringstream s;
  s.precision(1);
  s << std::fixed << 100.0 * std::abs(ratio - 1.0) << (ratio >= 1.0 ? " % more" : " % less");
  return s.str();
}

/// A heading taken from the gyro shows as an odometry topic that follows the gyro far more
/// closely than the robot's own wheels do, and turns differently from its wheels.
void findGyroHeading(SensorAgreement& s, const RotationSources& in) {
  std::vector<std::string>& findings = s.findings;
  const PairAgreement* og = s.pair("gyro", "odometry");
  const PairAgreement* wg = s.pair("wheels", "gyro");
  const PairAgreement* wo = s.pair("wheels", "odometry");
  if (og && wg && wo && og->kept > 0 && wg->kept > 0 && std::abs(og->scale - 1.0) < 0.02 &&
      og->rms_residual_rad < 0.5 * wg->rms_residual_rad && std::abs(wo->scale - 1.0) > 0.02)
    findings.push_back(
        "the odometry topic takes its heading from the gyro: it follows the gyro to " +
        fmtDeg(og->rms_residual_rad) +
        " deg RMS per window (the wheels: " + fmtDeg(wg->rms_residual_rad) +
        " deg) while the wheels, with the nominal "
        "geometry, turn " +
        fmtMoreOrLess(wo->scale) +
        " than it: a gyro-heading odometry (e.g. TurtleBot3's use_imu). "
        "Calibration uses the wheels, not the odometry topic");
  if (!og && wg && in.wheels && in.wheels->from == "odometry_poses" && wg->kept > 0 &&
      std::abs(wg->scale - 1.0) < 0.01 && wg->rms_residual_rad < 0.5 / kDeg) {
    s.wheels_follow_gyro = true;
    findings.push_back(
        "the odometry's heading follows the gyro to " + fmtDeg(wg->rms_residual_rad) +
        " deg RMS per window: if the robot takes its heading from the gyro (a gyro-heading "
        "odometry, e.g. TurtleBot3's use_imu), the wheel increments derived from its poses carry "
        "the gyro's rotation and the wheel base cannot be calibrated from them");
  }
}

}  // namespace

HeadingSeries wheelHeading(const WheelTrack& wheels, const DiffDriveParams& g) {
  HeadingSeries heading;
  heading.reserve(wheels.phi_rad.size());
  for (const auto& s : wheels.phi_rad.samples())
    heading.push_back(
        s.stamp_s, (g.radius_right_m * s.value(1) - g.radius_left_m * s.value(0)) / g.wheel_base_m);
  return heading;
}

const PairAgreement* SensorAgreement::pair(const std::string& a, const std::string& b) const {
  for (const PairAgreement& p : pairs)
    if (p.a == a && p.b == b) return &p;
  return nullptr;
}

const PairAgreement* SensorAgreement::wheelsScansConflict() const {
  if (pair("wheels", "gyro")) return nullptr;
  const PairAgreement* p = pair("wheels", "scans");
  return p && !p->disagreements.empty() ? p : nullptr;
}

const PairAgreement* SensorAgreement::wheelsGyroConflict() const {
  const PairAgreement* p = pair("wheels", "gyro");
  return p && !p->disagreements.empty() ? p : nullptr;
}

SensorAgreement compareSensors(const RotationSources& in, const AgreementParams& params) {
  SensorAgreement out;
  out.params = params;
  const std::vector<Source> sources = namedSources(in);
  out.shared_from_s = -std::numeric_limits<double>::infinity();
  out.shared_to_s = std::numeric_limits<double>::infinity();
  for (const Source& s : sources) {
    out.shared_from_s = std::max(out.shared_from_s, s.from());
    out.shared_to_s = std::min(out.shared_to_s, s.to());
  }
  if (sources.empty()) out.shared_from_s = out.shared_to_s = 0.0;
  for (const Source& s : sources)
    out.sources.push_back(turningOf(s, out.shared_from_s, out.shared_to_s, params));
  for (std::size_t i = 0; i < sources.size(); ++i)
    for (std::size_t j = i + 1; j < sources.size(); ++j)
      out.pairs.push_back(comparePair(sources[i], sources[j], params));
  findGyroHeading(out, in);
  return out;
}

}  // namespace slamprep::algo
