#include "slamprep/eval/bench/twin_lidar.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <numbers>
#include <optional>
#include <tuple>
#include <utility>

#include "slamprep/algo/timing/stamp_grid.hpp"
#include "slamprep/core/order_statistics.hpp"
#include "slamprep/eval/bench/transient_returns.hpp"
#include "slamprep/eval/metrics/error_stats.hpp"
#include "slamprep/eval/pipeline/match_trajectory.hpp"

namespace slamprep::eval {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

/// The simulator's beams start at -fov/2 (counter-clockwise) or +fov/2 (clockwise).
void simulatorLayout(LidarLayout& l) {
  const double inc = std::abs(l.angle_increment_rad);
  if (inc <= 0.0) return;
  l.beams_per_revolution = std::max(1, static_cast<int>(std::lround(kTwoPi / inc)));
  // A full turn's beams (an RPLIDAR's 720 over 359.5 deg, a Neato's 361 over 360 inclusive):
  // the count is the revolution's, whatever rounding the increment says.
  if (double(l.beams_mode) * inc >= 0.98 * kTwoPi) l.beams_per_revolution = int(l.beams_mode);
  const double step = kTwoPi / l.beams_per_revolution;
  l.fov_rad = std::min(kTwoPi, double(l.beams_mode) * step);
  const double sim_start = l.angle_increment_rad < 0.0 ? l.fov_rad / 2 : -l.fov_rad / 2;
  l.mount_yaw_shift_rad = std::remainder(l.angle_min_rad - sim_start, kTwoPi);
}

}  // namespace

LidarLayout fitLidarLayout(const Dataset& d) {
  LidarLayout l;
  l.scans = d.scans.size();
  if (d.scans.empty()) return l;
  std::vector<double> stamps, increments, times, mins, maxs;
  double longest = -1.0;  // the longest valid reading; -1: none
  std::map<std::size_t, std::size_t> counts;
  std::size_t beams = 0, invalid = 0;
  for (const ScanRecord& record : d.scans) {
    const LaserScan& s = record.scan;
    stamps.push_back(s.stamp_s);
    ++counts[s.size()];
    beams += s.size();
    increments.push_back(s.angle_increment_rad);
    times.push_back(s.time_increment_s);
    mins.push_back(s.range_min_m);
    maxs.push_back(s.range_max_m);
    for (std::size_t i = 0; i < s.size(); ++i) {
      if (s.valid(i))
        longest = std::max(longest, s.ranges_m[i]);
      else
        ++invalid;
    }
  }
  const double step = algo::streamPeriod(stamps);
  l.rate_hz = step > 0.0 ? 1.0 / step : 0.0;
  l.beams_per_scan_mean = double(beams) / double(d.scans.size());
  l.beams_min = counts.begin()->first;
  l.beams_max = counts.rbegin()->first;
  l.beams_mode = std::max_element(counts.begin(), counts.end(), [](auto a, auto b) {
                   return a.second < b.second;
                 })->first;
  for (const ScanRecord& r : d.scans)
    if (r.scan.size() == l.beams_mode) {
      l.angle_min_rad = r.scan.angle_min_rad;
      break;
    }
  l.angle_increment_rad = median(increments);
  l.time_increment_s = median(times);
  l.range_min_m = median(mins);
  l.range_max_m = median(maxs);
  // The longest return, not a percentile: a percentile would cut off returns the recording has
  // by construction (0.1 % of them at the 99.9th, 1.25x ACES's no-returns on its twin); how
  // returns thin out with range is the dropout pattern's job (keep_factor_by_range).
  l.usable_max_m = longest >= 0.0 ? std::min(l.range_max_m, longest) : l.range_max_m;
  l.no_return_fraction = beams > 0 ? double(invalid) / double(beams) : 0.0;
  simulatorLayout(l);
  return l;
}

namespace {

/// Beams and returns per (twin angle bin, range bin).
struct PatternCounts {
  std::vector<std::vector<double>> beams, returns;
  PatternCounts(std::size_t angle_bins, std::size_t range_bins)
      : beams(angle_bins, std::vector<double>(range_bins)),
        returns(angle_bins, std::vector<double>(range_bins)) {}
};

/// One half of an alternating fit: every factor of `fit` (by angle when by_angle, else by
/// range) such that its bin's expected returns, beams x K x factor x the other's factor, are the
/// returns seen; 1 for a bin without beams.
void fitHalf(const PatternCounts& c, double K, const std::vector<double>& other, bool by_angle,
             std::vector<double>& fit) {
  for (std::size_t i = 0; i < fit.size(); ++i) {
    double got = 0.0, expected = 0.0;
    for (std::size_t j = 0; j < other.size(); ++j) {
      const std::size_t a = by_angle ? i : j, r = by_angle ? j : i;
      got += c.returns[a][r];
      expected += c.beams[a][r] * K * other[j];
    }
    fit[i] = expected > 0.0 ? got / expected : 1.0;
  }
}

/// Separable factors on the chance of a return for a twin that drops twin_dropout of its beams
/// where its world has a wall, its recording dropout: keep(a, r) = (1 - twin_dropout) A[a] R[r]
/// fitted by alternating fits of A given R and of R given A (iterative proportional fitting of
/// a multiplicative model; the marginals alone would count the range's effect twice in bins that
/// see far walls more often) to the recording's returns with its drops scaled by twin_dropout /
/// dropout in every bin: the twin drops less where its escapes already give no-returns, in
/// proportion (fitted to the returns as seen, bins that almost never drop asked for returns
/// above 1, and the cap lost them: ACES's twin then missed 1.34x its recording's beams).
std::pair<std::vector<double>, std::vector<double>> keepFactors(PatternCounts c, double dropout,
                                                                double twin_dropout) {
  const std::size_t na = c.beams.size(), nr = na ? c.beams[0].size() : 0;
  std::vector<double> A(na, 1.0), R(nr, 1.0);
  const double K = 1.0 - twin_dropout;
  if (!(K > 0.0) || !(dropout > 0.0)) return {A, R};
  const double scale = twin_dropout / dropout;
  for (std::size_t a = 0; a < na; ++a)
    for (std::size_t r = 0; r < nr; ++r)
      c.returns[a][r] = c.beams[a][r] - scale * (c.beams[a][r] - c.returns[a][r]);
  for (int pass = 0; pass < 20; ++pass) {
    fitHalf(c, K, R, true, A);
    fitHalf(c, K, A, false, R);
  }
  return {A, R};
}

/// Robust correlation of the pairs (Gnanadesikan and Kettenring 1972): with s+ and s- the robust
/// scales (MAD) of x + y and x - y, (s+^2 - s-^2) / (s+^2 + s-^2). Pearson's would be decided by
/// the few runs of beams the world's walls miss by centimetres (a corner cut short).
double neighbourCorrelation(const std::vector<std::pair<double, double>>& pairs) {
  if (pairs.size() < 3) return 0.0;
  std::vector<double> sum, difference;
  for (const auto& [x, y] : pairs) {
    sum.push_back(x + y);
    difference.push_back(x - y);
  }
  const auto scale = [](std::vector<double>& v) {
    const double m = median(v);
    for (double& x : v) x = std::abs(x - m);
    return median(v);
  };
  const double s_plus = scale(sum), s_minus = scale(difference);
  const double total = s_plus * s_plus + s_minus * s_minus;
  return total > 0.0 ? (s_plus * s_plus - s_minus * s_minus) / total : 0.0;
}

/// A beam's predicted hit on the world and its residual.
struct BeamResidual {
  Eigen::Vector2d hit_world;
  double residual_m = 0.0;
};
using ScanResiduals = std::vector<std::optional<BeamResidual>>;  // by beam index

/// Pairs of residuals where a beam of `current` (its lidar at T_world_lidar, first beam) hit
/// within `distance_m` of where a beam of `previous` did: the beam pointing there is looked up
/// by its angle, the hits compared.
void revisitPairs(const ScanResiduals& previous, const ScanResiduals& current,
                  const LaserScan& scan, const SE2& T_world_lidar, double distance_m,
                  std::vector<std::pair<double, double>>& pairs) {
  const SE2 T_lidar_world = T_world_lidar.inverse();
  const double per_revolution = kTwoPi / std::abs(scan.angle_increment_rad);
  for (const auto& p : previous) {
    if (!p) continue;
    const Eigen::Vector2d q = T_lidar_world * p->hit_world;
    // Beams from the first to the one pointing at q, within one revolution.
    double beams = std::remainder(std::atan2(q.y(), q.x()) - scan.angle_min_rad, kTwoPi) /
                   scan.angle_increment_rad;
    if (beams < -0.5) beams += per_revolution;
    const long i = std::lround(beams);
    if (i < 0 || i >= static_cast<long>(current.size())) continue;
    const auto& c = current[static_cast<std::size_t>(i)];
    if (c && (c->hit_world - p->hit_world).norm() <= distance_m)
      pairs.push_back({p->residual_m, c->residual_m});
  }
}

/// Each beam's residuals, split by the half of the scans they came from.
struct BeamHalves {
  std::vector<double> sum[2], count[2];
  void add(std::size_t beam, bool second, double r) {
    for (int h = 0; h < 2; ++h)
      if (sum[h].size() <= beam) sum[h].resize(beam + 1), count[h].resize(beam + 1);
    sum[second][beam] += r;
    count[second][beam] += 1.0;
  }
};

double pearson(const std::vector<double>& x, const std::vector<double>& y) {
  const double n = double(x.size());
  double mx = 0.0, my = 0.0, sxy = 0.0, sxx = 0.0, syy = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) mx += x[i] / n, my += y[i] / n;
  for (std::size_t i = 0; i < x.size(); ++i) {
    sxy += (x[i] - mx) * (y[i] - my);
    sxx += (x[i] - mx) * (x[i] - mx);
    syy += (y[i] - my) * (y[i] - my);
  }
  return sxx > 0.0 && syy > 0.0 ? sxy / std::sqrt(sxx * syy) : 0.0;
}

/// LidarAgainstMap::residual_beam_halves_correlation and range_bias_by_beam_m.
void fitBeamBias(const BeamHalves& b, const LidarMapParams& p, LidarAgainstMap& m) {
  constexpr double kMinResiduals = 10.0;
  constexpr std::size_t kMinBeams = 30;
  const std::size_t beams = std::min(b.sum[0].size(), b.sum[1].size());
  std::vector<std::size_t> index;
  std::vector<double> first, second, whole;
  for (std::size_t i = 0; i < beams; ++i) {
    if (b.count[0][i] < kMinResiduals || b.count[1][i] < kMinResiduals) continue;
    index.push_back(i);
    first.push_back(b.sum[0][i] / b.count[0][i]);
    second.push_back(b.sum[1][i] / b.count[1][i]);
    whole.push_back((b.sum[0][i] + b.sum[1][i]) / (b.count[0][i] + b.count[1][i]));
  }
  if (index.size() < kMinBeams) return;
  const double rho = pearson(first, second);
  m.residual_beam_halves_correlation = rho;
  if (!(rho > std::max(3.0 / std::sqrt(double(index.size())), p.min_beam_halves_correlation)))
    return;
  // The share of the whole-recording means' variance the beams' own error makes (Spearman-
  // Brown: the reliability of a mean over both halves); scaled by its square root, the pattern
  // has the variance of that error, not of the means (its noise) nor of their best estimate
  // (less).
  const double reliability = 2.0 * rho / (1.0 + rho);
  double mean = 0.0;
  for (double w : whole) mean += w / double(whole.size());
  m.range_bias_by_beam_m.assign(beams, 0.0);
  for (std::size_t k = 0; k < index.size(); ++k)
    m.range_bias_by_beam_m[index[k]] = std::sqrt(reliability) * (whole[k] - mean);
}

}  // namespace

void dropBeamBiasBeyondResidual(double residual_m, LidarAgainstMap& m) {
  double sum2 = 0.0;
  std::size_t fitted = 0;
  for (double b : m.range_bias_by_beam_m)
    if (b != 0.0) sum2 += b * b, ++fitted;
  if (fitted == 0) return;
  const double rms_m = std::sqrt(sum2 / double(fitted));
  if (rms_m <= residual_m) return;
  char text[240];
  std::snprintf(text, sizeof text,
                "a pattern of %.1f mm RMS over %zu beams exceeds the recording's whole residual "
                "(%.1f mm): the walls' own errors seen by the same beams, not the lidar's",
                1e3 * rms_m, fitted, 1e3 * residual_m);
  m.range_bias_not_given = text;
  m.range_bias_by_beam_m.clear();
}

LidarAgainstMap compareWithMap(const Dataset& d, const PoseSeries& T_world_base,
                               const std::vector<char>& use, const sim::PlanarCaster& world,
                               const LidarLayout& layout, const LidarMapParams& p) {
  LidarAgainstMap m;
  const auto angle_bins = static_cast<std::size_t>(std::lround(360.0 / p.angle_bin_deg));
  const auto range_bins = static_cast<std::size_t>(
      std::ceil(std::max(layout.usable_max_m, p.range_bin_m) / p.range_bin_m));
  std::vector<std::size_t> by_angle(angle_bins), drop_angle(angle_bins);
  PatternCounts pattern(angle_bins, range_bins);
  const auto angleBin = [&](double angle_rad) {
    const double turn = (std::remainder(angle_rad, kTwoPi) + std::numbers::pi) / kTwoPi;
    return std::min(angle_bins - 1, static_cast<std::size_t>(turn * double(angle_bins)));
  };
  std::vector<std::size_t> drop_range(range_bins);
  m.predicted_by_range.assign(range_bins, 0);
  std::vector<double> residuals;
  std::vector<std::pair<double, double>> neighbours;  // residuals of beams i - 1 and i
  std::vector<std::pair<double, double>> revisits;    // one spot's residuals in two scans
  ScanResiduals previous_scan;
  BeamHalves halves;
  const bool one_layout = layout.beams_min == layout.beams_max;
  std::size_t predicted = 0, dropped = 0, unpredicted = 0, spurious = 0;
  for (std::size_t k = 0; k < d.scans.size() && k < use.size(); ++k) {
    if (!use[k]) {
      previous_scan.clear();
      continue;
    }
    const LaserScan& s = d.scans[k].scan;
    ScanResiduals this_scan(s.size());
    std::optional<double> last;  // beam i - 1's residual
    for (std::size_t i = 0; i < s.size(); ++i) {
      const std::optional<double> previous = std::exchange(last, std::nullopt);
      const auto T = T_world_base.at(s.beamTime(i));
      if (!T) continue;
      ++m.beams;
      const SE2 T_world_lidar = *T * d.info.T_base_lidar;
      const double a = T_world_lidar.yaw + s.beamAngle(i);
      const auto hit = world.cast(T_world_lidar.translation(), {std::cos(a), std::sin(a)},
                                  p.lidar_height_m, layout.usable_max_m);
      const bool valid = s.valid(i) && s.ranges_m[i] <= layout.usable_max_m;
      if (!hit) {
        ++unpredicted;
        if (valid) ++spurious;
        continue;
      }
      ++predicted;
      const std::size_t ab = angleBin(s.beamAngle(i));
      const std::size_t tb = angleBin(s.beamAngle(i) - layout.mount_yaw_shift_rad);
      const auto rb = std::min(range_bins - 1, static_cast<std::size_t>(*hit / p.range_bin_m));
      ++by_angle[ab];
      ++m.predicted_by_range[rb];
      ++pattern.beams[tb][rb];
      if (!valid) {
        ++dropped;
        ++drop_angle[ab];
        ++drop_range[rb];
        continue;
      }
      ++pattern.returns[tb][rb];
      const double r = s.ranges_m[i] - *hit;
      if (std::abs(r) > p.max_residual_m) continue;
      residuals.push_back(r);
      if (one_layout) halves.add(i, 2 * k >= d.scans.size(), r);
      if (previous) neighbours.push_back({*previous, r});
      last = r;
      this_scan[i] = BeamResidual{
          T_world_lidar.translation() + *hit * Eigen::Vector2d(std::cos(a), std::sin(a)), r};
    }
    if (const auto T = T_world_base.at(s.beamTime(0)); T && !previous_scan.empty())
      revisitPairs(previous_scan, this_scan, s, *T * d.info.T_base_lidar, p.revisit_distance_m,
                   revisits);
    previous_scan = std::move(this_scan);
  }
  m.residuals = residuals.size();
  m.residual_median_m = median(residuals);
  for (double& r : residuals) r = std::abs(r - m.residual_median_m);
  m.range_noise_m = 1.4826 * median(residuals);  // robust sigma: people and clutter are outliers
  m.residual_neighbour_correlation = neighbourCorrelation(neighbours);
  m.residual_revisit_correlation = neighbourCorrelation(revisits);
  fitBeamBias(halves, p, m);
  m.dropout_probability = predicted > 0 ? double(dropped) / double(predicted) : 0.0;
  m.spurious_fraction = unpredicted > 0 ? double(spurious) / double(unpredicted) : 0.0;
  if (m.beams > 0) {
    m.escape_fraction = double(unpredicted) / double(m.beams);
    m.no_return_fraction = double(dropped + unpredicted - spurious) / double(m.beams);
    if (m.escape_fraction < 1.0)
      m.twin_dropout_probability =
          std::max(0.0, (m.no_return_fraction - m.escape_fraction) / (1.0 - m.escape_fraction));
  }
  for (std::size_t b = 0; b < angle_bins; ++b)
    m.dropout_by_angle.push_back(by_angle[b] ? double(drop_angle[b]) / double(by_angle[b]) : 0.0);
  for (std::size_t b = 0; b < range_bins; ++b)
    m.dropout_by_range.push_back(
        m.predicted_by_range[b] ? double(drop_range[b]) / double(m.predicted_by_range[b]) : 0.0);
  std::tie(m.keep_factor_by_twin_angle, m.keep_factor_by_range) =
      keepFactors(pattern, m.dropout_probability, m.twin_dropout_probability);
  return m;
}

std::vector<MapPoint> matchedMapPoints(const MatchTrajectory& run,
                                       const std::vector<Points2>& points, double usable_max_m,
                                       std::vector<char>& accepted) {
  std::vector<MapPoint> map;
  accepted.assign(points.size(), 0);
  for (std::size_t k = 0; k < points.size(); ++k) {
    const algo::TrackedScan& t = run.tracked.scans[k];
    if (k > 0 && t.fallback) continue;
    accepted[k] = 1;
    for (const Eigen::Vector2d& p : points[k])
      if (p.norm() <= usable_max_m)
        map.push_back({t.T_world_lidar * p, t.T_world_lidar.translation()});
  }
  return map;
}

namespace {

/// The matched poses at the times they stand for (a sweep matched as measured: its middle), so
/// that each beam is cast from where the base was.
PoseSeries matchedPoses(const MatchTrajectory& run) {
  PoseSeries out;
  for (std::size_t k = 0; k < run.T_world_base.size(); ++k)
    out.push_back(run.pose_time_s[k], run.T_world_base.samples()[k].value);
  return out;
}

}  // namespace

ResidualCorrelations ownMapCorrelations(const Dataset& d, const LidarLayout& layout,
                                        const WallExtractionParams& walls,
                                        const LidarMapParams& params, bool count_transients) {
  const ScanPoints points = matchScanPoints(d, "vicp", false);
  const MatchTrajectory run = matchTrajectory(d, points, twinMatchOptions());
  return ownMapCorrelations(d, points, run, layout, walls, params, count_transients);
}

ResidualCorrelations ownMapCorrelations(const Dataset& d, const ScanPoints& points,
                                        const MatchTrajectory& run, const LidarLayout& layout,
                                        const WallExtractionParams& walls,
                                        const LidarMapParams& params, bool count_transients) {
  std::vector<char> accepted;
  const WallMap map =
      extractWalls(matchedMapPoints(run, points.points, layout.usable_max_m, accepted), walls);
  const sim::PlanarCaster world(wallsAsWorld(map, walls));
  const PoseSeries T_world_base = matchedPoses(run);
  const LidarAgainstMap m = compareWithMap(d, T_world_base, accepted, world, layout, params);
  return {m.residual_neighbour_correlation, m.residual_revisit_correlation,
          count_transients
              ? transientReturns(d, T_world_base, accepted, layout.usable_max_m).fraction()
              : 0.0};
}

namespace {

MatchedScans withCorrelations(const Dataset& d, const ResidualCorrelations& c) {
  const MatchTrajectory run =
      matchTrajectory(d, matchScanPoints(d, "none", false), twinMatchOptions());
  std::vector<double> rms;
  for (std::size_t k = 1; k < run.tracked.scans.size(); ++k)
    if (!run.tracked.scans[k].fallback) rms.push_back(run.tracked.scans[k].match.rms_residual_m);
  MatchedScans m;
  if (const ErrorStats s = summarize(std::move(rms)); s.ok) m.residual_median_m = s.median;
  m.neighbour_correlation = c.neighbour;
  m.revisit_correlation = c.revisit;
  return m;
}

}  // namespace

MatchedScans measureMatchedScans(const Dataset& d, const LidarLayout& layout,
                                 const WallExtractionParams& walls, const LidarMapParams& params) {
  return withCorrelations(d, ownMapCorrelations(d, layout, walls, params));
}

MatchedScans measureMatchedScans(const Dataset& d, const ScanPoints& vicp_points,
                                 const MatchTrajectory& vicp_run, const LidarLayout& layout,
                                 const WallExtractionParams& walls, const LidarMapParams& params) {
  return withCorrelations(d, ownMapCorrelations(d, vicp_points, vicp_run, layout, walls, params));
}

}  // namespace slamprep::eval
