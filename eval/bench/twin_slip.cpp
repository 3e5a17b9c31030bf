#include "slamprep/eval/bench/twin_slip.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "slamprep/core/odometry.hpp"

namespace slamprep::eval {
namespace {

/// One piece of path: its heading error and the slip model's regressor Q of Eq. (1).
struct Piece {
  double error_rad = 0.0;
  double q = 0.0;
};

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

/// Q of Eq. (1): (2 tau / b^2) sum over the encoder steps inside [t0, t1] of (ds_L^2 + ds_R^2)/dt.
double slipRegressor(const OdometryEncoders& enc, const DiffDriveParams& g, double tau_s, double t0,
                     double t1) {
  const double rad_per_tick = radiansPerTick(enc.ticks_per_revolution);
  double sum = 0.0;
  const EncoderLog& e = enc.encoders;
  const auto first = std::lower_bound(
      e.begin(), e.end(), t0, [](const EncoderSample& s, double t) { return s.stamp_s < t; });
  for (std::size_t k = std::max<std::size_t>(1, first - e.begin() + 1);
       k < e.size() && e[k].stamp_s <= t1; ++k) {
    const double dt = e[k].stamp_s - e[k - 1].stamp_s;
    if (dt <= 0.0) continue;
    const double ds_l =
        g.radius_left_m * rad_per_tick * double(e[k].ticks_left - e[k - 1].ticks_left);
    const double ds_r =
        g.radius_right_m * rad_per_tick * double(e[k].ticks_right - e[k - 1].ticks_right);
    sum += (ds_l * ds_l + ds_r * ds_r) / dt;
  }
  const double ratio = tau_s / (t1 - t0);
  const double finite_piece = 1.0 - ratio * (1.0 - std::exp(-1.0 / ratio));
  return 2.0 * tau_s * finite_piece * sum / (g.wheel_base_m * g.wheel_base_m);
}

double headingChange(const PoseSeries& series, double t0, double t1) {
  return normalizeAngle(series.at(t1)->yaw - series.at(t0)->yaw);
}

using Line = std::pair<double, double>;  ///< (sigma^2, c) of Eq. (1)

/// Weighted least squares of y = a x + c, y the squared error, x = Q; c held at 0 when it
/// comes out negative.
Line fitLine(const std::vector<Piece>& pieces, const std::vector<double>& weights) {
  double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    const double w = weights[k], x = pieces[k].q, y = pieces[k].error_rad * pieces[k].error_rad;
    n += w;
    sx += w * x;
    sy += w * y;
    sxx += w * x * x;
    sxy += w * x * y;
  }
  const double det = n * sxx - sx * sx;
  double a = det > 0.0 ? (n * sxy - sx * sy) / det : 0.0;
  double c = det > 0.0 ? (sy - a * sx) / n : sy / n;
  if (c < 0.0) {  // through the origin
    c = 0.0;
    a = sxx > 0.0 ? sxy / sxx : 0.0;
  }
  return {std::max(0.0, a), c};
}

/// The squared error of a Gaussian piece has variance 2 (sigma^2 Q + c)^2: weights 1 / that,
/// from the line of the previous pass (Gaussian maximum likelihood, iteratively reweighted).
/// The first pass assumes slip only (c = 0), so a long piece does not outweigh many short ones.
Line fitReweighted(const std::vector<Piece>& pieces) {
  std::vector<double> weights(pieces.size());
  Line line{1.0, 0.0};
  for (int pass = 0; pass < 4; ++pass) {
    for (std::size_t k = 0; k < pieces.size(); ++k) {
      const double predicted = line.first * pieces[k].q + line.second;
      weights[k] = predicted > 0.0 ? 1.0 / (predicted * predicted) : 0.0;
    }
    line = fitLine(pieces, weights);
    if (line.first <= 0.0 && line.second <= 0.0) break;  // nothing to weigh by
  }
  return line;
}

/// The pieces within outlier_sigmas of what the line (sigma^2, c) predicts for them.
std::vector<Piece> withoutOutliers(const std::vector<Piece>& pieces, const Line& line,
                                   const WheelSlipParams& params) {
  const auto [sigma2, c] = line;
  std::vector<Piece> kept;
  for (const Piece& p : pieces) {
    const double predicted = sigma2 * p.q + c;
    if (p.error_rad * p.error_rad <= params.outlier_sigmas * params.outlier_sigmas * predicted)
      kept.push_back(p);
  }
  return kept;
}

}  // namespace

WheelSlipFit fitWheelSlip(const OdometryEncoders& encoders, const DiffDriveParams& g,
                          const PoseSeries& reference, const WheelSlipParams& params) {
  WheelSlipFit fit;
  fit.tau_s = params.tau_s;
  if (encoders.encoders.size() < 2) return fit;
  const PoseSeries odometry = integrateOdometry(encoders, g);
  const double max_error = params.max_heading_error_deg * std::numbers::pi / 180.0;
  std::vector<std::pair<double, double>> stamps;
  for (const double duration_s : params.piece_s) {
    const auto cut = pieceStamps(reference, duration_s, params);
    stamps.insert(stamps.end(), cut.begin(), cut.end());
  }
  std::vector<Piece> pieces;
  for (const auto& [t0, t1] : stamps) {
    if (!odometry.covers(t0) || !odometry.covers(t1)) continue;
    const double error =
        normalizeAngle(headingChange(odometry, t0, t1) - headingChange(reference, t0, t1));
    const double q = slipRegressor(encoders, g, params.tau_s, t0, t1);
    if (std::abs(error) <= max_error && q > 0.0) pieces.push_back({error, q});
  }
  fit.pieces = pieces.size();
  if (pieces.size() < params.min_pieces) return fit;
  const std::vector<Piece> kept = withoutOutliers(pieces, fitReweighted(pieces), params);
  fit.pieces = kept.size();
  fit.fitted = kept.size() >= params.min_pieces;
  if (!fit.fitted) return fit;
  const auto [sigma2, c] = fitReweighted(kept);
  fit.sigma = std::sqrt(sigma2);
  fit.reference_noise_rad = std::sqrt(c);
  return fit;
}

}  // namespace slamprep::eval
