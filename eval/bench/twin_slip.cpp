#include "slamprep/eval/bench/twin_slip.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <vector>

#include "slamprep/core/odometry.hpp"

namespace slamprep::eval {
namespace {

constexpr int kVariances = 4;
using Vector = Eigen::Matrix<double, kVariances, 1>;
using Matrix = Eigen::Matrix<double, kVariances, kVariances>;

/// One piece of path: its heading error and the regressors of Eq. (1): Q (wheel slip), Q_turn
/// (slip in turns), W (the wheels read off their stamps) and 1 (the reference's own noise).
struct Piece {
  double error_rad = 0.0;
  Vector x = Vector::Zero();
  /// Variance taken as known, not fitted: Eq. (2)'s wheel slip term; Eq. (1)'s held ones.
  double known = 0.0;
  double predicted(const Vector& v) const { return v.dot(x) + known; }
};

/// (sigma^2, sigma_turn^2, sigma_t^2, c) of Eq. (1).
using Variances = Vector;

/// Pieces of duration_s along the reference, one after another; a piece with a step longer
/// than max_gap_s (matches missing) is left out.
std::vector<std::pair<double, double>> pieceStamps(const PoseSeries& reference, double duration_s,
                                                   const WheelSlipParams& params) {
  std::vector<std::pair<double, double>> out;
  const auto& s = reference.samples();
  std::size_t start = 0;
  bool gap = false;
  for (std::size_t k = 1; k < s.size(); ++k) {
    gap = gap || s[k].stamp_s - s[k - 1].stamp_s > params.max_gap_s;
    if (s[k].stamp_s - s[start].stamp_s < duration_s) continue;
    if (!gap) out.emplace_back(s[start].stamp_s, s[k].stamp_s);
    start = k;
    gap = false;
  }
  return out;
}

/// sum_i sum_j a_i a_j exp(-|t_i - t_j| / tau) over the encoder steps i, j of a piece, by the
/// recursion h_i = exp(-(t_i - t_(i-1)) / tau) (h_(i-1) + a_(i-1)): the variance of sum_i a_i s_i
/// per sigma^2 for an Ornstein-Uhlenbeck s held over each step, as sim::WheelSlip counts it.
class CorrelatedSum {
 public:
  explicit CorrelatedSum(double tau_s) : tau_s_(tau_s) {}
  void add(double a, double t_s) {
    if (any_) h_ = std::exp(-(t_s - t_s_) / tau_s_) * (h_ + a_);
    sum_ += a * a + 2.0 * a * h_;
    a_ = a, t_s_ = t_s, any_ = true;
  }
  double sum() const { return sum_; }

 private:
  double tau_s_, sum_ = 0.0, h_ = 0.0, a_ = 0.0, t_s_ = 0.0;
  bool any_ = false;
};

/// Q and Q_turn of Eq. (1) over the encoder steps inside [t0, t1].
Eigen::Vector2d slipRegressors(const OdometryEncoders& enc, const DiffDriveParams& g, double tau_s,
                               double t0, double t1) {
  const double rad_per_tick = radiansPerTick(enc.ticks_per_revolution);
  CorrelatedSum left(tau_s), right(tau_s), turn(tau_s);
  const EncoderLog& e = enc.encoders;
  const auto first = std::lower_bound(
      e.begin(), e.end(), t0, [](const EncoderSample& s, double t) { return s.stamp_s < t; });
  for (std::size_t k = std::max<std::size_t>(1, first - e.begin() + 1);
       k < e.size() && e[k].stamp_s <= t1; ++k) {
    const double ds_l =
        g.radius_left_m * rad_per_tick * double(e[k].ticks_left - e[k - 1].ticks_left);
    const double ds_r =
        g.radius_right_m * rad_per_tick * double(e[k].ticks_right - e[k - 1].ticks_right);
    left.add(ds_l, e[k].stamp_s);
    right.add(ds_r, e[k].stamp_s);
    turn.add((ds_r - ds_l) / g.wheel_base_m, e[k].stamp_s);
  }
  return {(left.sum() + right.sum()) / (g.wheel_base_m * g.wheel_base_m), turn.sum()};
}

double headingChange(const PoseSeries& series, double t0, double t1) {
  return normalizeAngle(series.at(t1)->yaw - series.at(t0)->yaw);
}

/// The turn rate at t, over span_s around it (within the series).
double turnRate(const PoseSeries& series, double t, double span_s) {
  const double a = std::max(series.frontStamp(), t - 0.5 * span_s);
  const double b = std::min(series.backStamp(), t + 0.5 * span_s);
  return b > a ? headingChange(series, a, b) / (b - a) : 0.0;
}

/// Weighted least squares of the squared errors on the regressors in `subset` (bit i set: the
/// variance i is fitted; clear: held at 0).
std::optional<Variances> fitSubset(const std::vector<Piece>& pieces,
                                   const std::vector<double>& weights, int subset) {
  Vector on;
  for (int i = 0; i < kVariances; ++i) on(i) = (subset >> i) & 1;
  // A variance held at 0 gets a 1 on the diagonal, so that A stays invertible.
  Matrix A = Matrix((Vector::Ones() - on).asDiagonal());
  Vector rhs = Vector::Zero();
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    const Vector x = pieces[k].x.cwiseProduct(on);
    A += weights[k] * x * x.transpose();
    rhs += weights[k] * x * (pieces[k].error_rad * pieces[k].error_rad - pieces[k].known);
  }
  const Eigen::FullPivLU<Matrix> lu(A);
  if (!lu.isInvertible()) return std::nullopt;
  return Variances(lu.solve(rhs));
}

/// Which variances a fit may use (bit i: variance i).
constexpr int kAllVariances = (1 << kVariances) - 1;
constexpr int kTiming = 1 << 2;

/// Gaussian log-likelihood of the pieces' errors under the variances, over `durations`: the
/// pieces of every duration cover the same stretch, which is counted once.
double logLikelihood(const std::vector<Piece>& pieces, const Variances& v, std::size_t durations,
                     double floor) {
  double sum = 0.0;
  for (const Piece& p : pieces) {
    const double variance = std::max(floor, p.predicted(v));
    sum -= 0.5 * (std::log(variance) + p.error_rad * p.error_rad / variance);
  }
  return sum / double(std::max<std::size_t>(1, durations));
}

/// The variances in `subset` (the others 0) by Gaussian maximum likelihood: the least squares of
/// dtheta^2 reweighted by 1 / (predicted variance)^2, the inverse of a Gaussian dtheta^2's
/// variance 2 (v . x)^2 (Fisher scoring), until it settles. The first pass assumes slip only
/// (c = 0), so a long piece does not outweigh many short ones. nullopt where a variance comes
/// out negative once it has settled: its maximum lies on a smaller subset. (Judged on the first
/// pass, the start's weights decided: a reference noise held at (8 mrad)^2 made the turn slip of
/// a Neato's spins come out negative there, from the many straight pieces whose error is less.)
std::optional<Variances> fitSubsetByLikelihood(const std::vector<Piece>& pieces, double floor,
                                               int subset) {
  constexpr int kPasses = 12;
  std::vector<double> weights(pieces.size());
  Variances v(1.0, 1.0, 0.0, 0.0);
  for (int pass = 0; pass < kPasses; ++pass) {
    for (std::size_t k = 0; k < pieces.size(); ++k) {
      const double predicted = std::max(floor, pieces[k].predicted(v.cwiseMax(0.0)));
      weights[k] = 1.0 / (predicted * predicted);
    }
    const std::optional<Variances> next = fitSubset(pieces, weights, subset);
    if (!next) return std::nullopt;
    v = *next;
  }
  if ((v.array() < 0.0).any()) return std::nullopt;
  return v;
}

/// The maximum likelihood with every variance >= 0: the most likely of the fits on the subsets
/// of the `allowed` variances.
Variances fitMostLikely(const std::vector<Piece>& pieces, double floor, int allowed) {
  Variances best = Variances::Zero();
  double best_likelihood = -std::numeric_limits<double>::infinity();
  for (int subset = 1; subset < (1 << kVariances); ++subset) {
    if ((subset & ~allowed) != 0) continue;
    const std::optional<Variances> v = fitSubsetByLikelihood(pieces, floor, subset);
    if (!v) continue;
    const double likelihood = logLikelihood(pieces, *v, 1, floor);
    if (likelihood > best_likelihood) best_likelihood = likelihood, best = *v;
  }
  return best;
}

/// The pieces within outlier_sigmas of what the variances predict for them.
std::vector<Piece> withoutOutliers(const std::vector<Piece>& pieces, const Variances& v,
                                   double sigmas) {
  std::vector<Piece> kept;
  for (const Piece& p : pieces)
    if (p.error_rad * p.error_rad <= sigmas * sigmas * p.predicted(v)) kept.push_back(p);
  return kept;
}

/// The pieces of every duration along the reference, as (t0, t1) within the odometry.
std::vector<std::pair<double, double>> allPieces(const PoseSeries& reference,
                                                 const PoseSeries& odometry,
                                                 const WheelSlipParams& params) {
  std::vector<std::pair<double, double>> stamps;
  for (const double duration_s : params.piece_s)
    for (const auto& [t0, t1] : pieceStamps(reference, duration_s, params))
      if (odometry.covers(t0) && odometry.covers(t1)) stamps.emplace_back(t0, t1);
  return stamps;
}

/// Eq. (1)'s sigmas held by `params` (sigma, sigma_turn, sigma_t, sqrt(c)): < 0 where fitted.
Vector heldHeadingSigmas(const WheelSlipParams& params) {
  return {params.slip_sigma, params.turn_slip_sigma, -1.0, params.reference_noise_rad};
}

/// Which of Eq. (1)'s variances `params` leaves to the fit.
int fittedHeadingVariances(const WheelSlipParams& params) {
  const Vector held = heldHeadingSigmas(params);
  int fitted = 0;
  for (int i = 0; i < kVariances; ++i)
    if (held(i) < 0.0) fitted |= 1 << i;
  return fitted;
}

/// The pieces' heading errors and Eq. (1)'s regressors.
std::vector<Piece> headingPieces(const OdometryEncoders& encoders, const DiffDriveParams& g,
                                 const PoseSeries& reference, const PoseSeries& odometry,
                                 const WheelSlipParams& params) {
  const double max_error = params.max_heading_error_deg * std::numbers::pi / 180.0;
  const Vector held = heldHeadingSigmas(params);
  std::vector<Piece> pieces;
  for (const auto& [t0, t1] : allPieces(reference, odometry, params)) {
    const double error =
        normalizeAngle(headingChange(odometry, t0, t1) - headingChange(reference, t0, t1));
    const Eigen::Vector2d q = slipRegressors(encoders, g, params.tau_s, t0, t1);
    if (std::abs(error) <= max_error && q(0) > 0.0) {
      const double w0 = turnRate(odometry, t0, params.rate_span_s);
      const double w1 = turnRate(odometry, t1, params.rate_span_s);
      Piece p{error, Vector(q(0), q(1), w0 * w0 + w1 * w1, 1.0)};
      for (int i = 0; i < kVariances; ++i)
        if (held(i) >= 0.0) {  // its variance known, its regressor out
          p.known += held(i) * held(i) * p.x(i);
          p.x(i) = 0.0;
        }
      pieces.push_back(p);
    }
  }
  return pieces;
}

double chord(const PoseSeries& series, double t0, double t1) {
  return (series.at(t1)->translation() - series.at(t0)->translation()).norm();
}

/// The speed along `direction` at t, over span_s around it (within the series).
double speedAlong(const PoseSeries& series, const Eigen::Vector2d& direction, double t,
                  double span_s) {
  const double a = std::max(series.frontStamp(), t - 0.5 * span_s);
  const double b = std::min(series.backStamp(), t + 0.5 * span_s);
  if (!(b > a)) return 0.0;
  return direction.dot(series.at(b)->translation() - series.at(a)->translation()) / (b - a);
}

/// Eq. (2)'s regressors over the encoder steps inside [t0, t1]: C and R
/// (the wheel slip term's).
Eigen::Vector2d distanceRegressors(const OdometryEncoders& enc, const DiffDriveParams& g,
                                   const PoseSeries& odometry, const Eigen::Vector2d& direction,
                                   double tau_s, double t0, double t1) {
  const double rad_per_tick = radiansPerTick(enc.ticks_per_revolution);
  CorrelatedSum common(tau_s), left(tau_s), right(tau_s);
  const EncoderLog& e = enc.encoders;
  const auto first = std::lower_bound(
      e.begin(), e.end(), t0, [](const EncoderSample& s, double t) { return s.stamp_s < t; });
  for (std::size_t k = std::max<std::size_t>(1, first - e.begin() + 1);
       k < e.size() && e[k].stamp_s <= t1; ++k) {
    const double yaw = odometry.at(e[k].stamp_s)->yaw;
    const double a = direction.dot(Eigen::Vector2d(std::cos(yaw), std::sin(yaw)));
    const double ds_l =
        a * g.radius_left_m * rad_per_tick * double(e[k].ticks_left - e[k - 1].ticks_left);
    const double ds_r =
        a * g.radius_right_m * rad_per_tick * double(e[k].ticks_right - e[k - 1].ticks_right);
    common.add(0.5 * (ds_l + ds_r), e[k].stamp_s);
    left.add(ds_l, e[k].stamp_s);
    right.add(ds_r, e[k].stamp_s);
  }
  return {common.sum(), left.sum() + right.sum()};
}

/// The pieces that turn little: their distance errors, Eq. (2)'s C, W, V and 1 as regressors and
/// its wheel slip term as known, from the heading fit's sigma.
std::vector<Piece> distancePieces(const OdometryEncoders& encoders, const DiffDriveParams& g,
                                  const PoseSeries& reference, const PoseSeries& odometry,
                                  const WheelSlipFit& heading, const WheelSlipParams& params) {
  const double max_turn = params.max_distance_turn_deg * std::numbers::pi / 180.0;
  const double slip2 = heading.sigma * heading.sigma;
  std::vector<Piece> pieces;
  for (const auto& [t0, t1] : allPieces(reference, odometry, params)) {
    if (std::abs(headingChange(odometry, t0, t1)) > max_turn) continue;
    const double error = chord(odometry, t0, t1) - chord(reference, t0, t1);
    if (!(std::abs(error) <= params.max_distance_error_m)) continue;
    const Eigen::Vector2d along = odometry.at(t1)->translation() - odometry.at(t0)->translation();
    const Eigen::Vector2d direction =
        along.norm() > 0.0 ? Eigen::Vector2d(along.normalized()) : Eigen::Vector2d::UnitX();
    const Eigen::Vector2d q =
        distanceRegressors(encoders, g, odometry, direction, params.tau_s, t0, t1);
    const double v0 = speedAlong(odometry, direction, t0, params.rate_span_s);
    const double v1 = speedAlong(odometry, direction, t1, params.rate_span_s);
    const double w0 = turnRate(odometry, t0, params.rate_span_s);
    const double w1 = turnRate(odometry, t1, params.rate_span_s);
    Piece p{error, Vector(q(0), w0 * w0 + w1 * w1, v0 * v0 + v1 * v1, 1.0)};
    p.known = slip2 * q(1) / 4.0;
    pieces.push_back(p);
  }
  return pieces;
}

/// The pieces' variances by maximum likelihood, outliers left out and the fit repeated, with
/// the variance `tested` (its bit) kept only where it raises the likelihood beyond `min_ratio`
/// (Wilks; the log-likelihood divided by the durations, whose pieces cover each stretch once).
struct TestedFit {
  std::size_t pieces = 0;  ///< after the outliers
  bool fitted = false;     ///< at least min_pieces
  Variances v = Variances::Zero();
  double likelihood_ratio = 0.0;  ///< 2 (log L with the tested variance - log L without)
};

TestedFit fitWithTest(std::vector<Piece> pieces, double floor, int allowed, int tested,
                      double min_ratio, const WheelSlipParams& params) {
  TestedFit fit;
  fit.pieces = pieces.size();
  if (pieces.size() < params.min_pieces) return fit;
  // Outliers inflate the first fit's variances, and so the bound that judges them: left out
  // and refitted until the kept set repeats.
  for (std::size_t before = 0; before != pieces.size() && pieces.size() >= params.min_pieces;) {
    before = pieces.size();
    pieces = withoutOutliers(pieces, fitMostLikely(pieces, floor, allowed), params.outlier_sigmas);
  }
  fit.pieces = pieces.size();
  fit.fitted = pieces.size() >= params.min_pieces;
  if (!fit.fitted) return fit;
  fit.v = fitMostLikely(pieces, floor, allowed);
  const Variances without = fitMostLikely(pieces, floor, allowed & ~tested);
  const std::size_t durations = params.piece_s.size();
  fit.likelihood_ratio = 2.0 * (logLikelihood(pieces, fit.v, durations, floor) -
                                logLikelihood(pieces, without, durations, floor));
  if (!(fit.likelihood_ratio > min_ratio)) fit.v = without;
  return fit;
}

/// Eq. (1) on the heading pieces: the wheel slip, the turn slip, the timing and the reference's
/// heading noise. The timing and the turn slip both show in turns: on a short recording they
/// are told apart by chance, so the timing is tested.
void fitHeading(std::vector<Piece> pieces, const WheelSlipParams& params, WheelSlipFit& fit) {
  const TestedFit t =
      fitWithTest(std::move(pieces), params.min_sigma_rad * params.min_sigma_rad,
                  fittedHeadingVariances(params), kTiming, params.timing_likelihood_ratio, params);
  fit.pieces = t.pieces;
  fit.fitted = t.fitted;
  if (!t.fitted) return;
  fit.timing_likelihood_ratio = t.likelihood_ratio;
  const Vector held = heldHeadingSigmas(params);
  const auto sigma = [&](int i) { return held(i) >= 0.0 ? held(i) : std::sqrt(t.v(i)); };
  fit.sigma = sigma(0);
  fit.turn_sigma = sigma(1);
  fit.timing_jitter_s = sigma(2);
  fit.reference_noise_rad = sigma(3);
}

/// Eq. (2) on the distance pieces: the common slip and the reference's distance noise (its
/// constant; its terms in turns and in speed are not reported). The reference's own terms can
/// take a common slip's variance and the slip theirs, so the slip is tested.
void fitDistance(std::vector<Piece> pieces, const WheelSlipParams& params, WheelSlipFit& fit) {
  constexpr int kCommon = 1 << 0;
  const TestedFit t = fitWithTest(std::move(pieces), params.min_sigma_m * params.min_sigma_m,
                                  kAllVariances, kCommon, params.common_likelihood_ratio, params);
  fit.distance_pieces = t.pieces;
  fit.common_fitted = t.fitted;
  if (!t.fitted) return;
  fit.common_likelihood_ratio = t.likelihood_ratio;
  fit.common_sigma = std::sqrt(t.v(0));
  fit.reference_distance_noise_m = std::sqrt(t.v(3));
}

}  // namespace

WheelSlipFit fitWheelSlip(const OdometryEncoders& encoders, const DiffDriveParams& g,
                          const PoseSeries& reference, const WheelSlipParams& params) {
  WheelSlipFit fit;
  fit.tau_s = params.tau_s;
  if (encoders.encoders.size() < 2) return fit;
  const PoseSeries odometry = integrateOdometry(encoders, g);
  fitHeading(headingPieces(encoders, g, reference, odometry, params), params, fit);
  if (fit.fitted)
    fitDistance(distancePieces(encoders, g, reference, odometry, fit, params), params, fit);
  return fit;
}

}  // namespace slamprep::eval
