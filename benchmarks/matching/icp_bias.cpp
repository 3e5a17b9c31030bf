// Bias of point-to-line ICP under range noise, in isolation: static 720-beam scans of room.yaml
// from random poses near the room's centre, the second scan after a known base motion (a spin
// about the base with the lidar mounted as the simulator mounts it, or a step forward), 1 cm
// range noise. Prints the mean and spread of the match error over many draws, and the error
// correlation of two consecutive matches that share their middle scan. Not a test: it measures
// what docs/design.md ("Calibration: is the reported sigma honest?") reports.
// Run: icp_bias [draws=40000] [yaw_per_scan_rad=0.1] [forward_per_scan_m=0] [noisy=both]
//   noisy: both | ref (reference scan only) | cur (current scan only) | chain (three scans,
//   consecutive-match correlation).
// The matcher's settings from the environment (the library's defaults otherwise): GATE=k sets
// IcpParams::outlier_sigmas, TRIM=f trim_fraction; SYM=1 averages each match with the inverse
// of the backward match (cur onto ref).

#include <Eigen/Core>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <random>
#include <string>

#include "slamprep/algo/matching/icp.hpp"
#include "slamprep/sim/physics/planar_caster.hpp"
#include "slamprep/sim/physics/world.hpp"

namespace {

using slamprep::between;
using slamprep::Points2;
using slamprep::SE2;

const SE2 kBaseLidar(0.1, 0.02, M_PI / 180.0);  // the simulator's default mount
constexpr double kRangeNoiseM = 0.01;

/// One static scan from T_world_lidar, Gaussian range noise of sigma noise_m.
Points2 scan(const slamprep::sim::PlanarCaster& caster, const SE2& T_world_lidar, double noise_m,
             std::mt19937_64& rng) {
  std::normal_distribution<double> noise(0.0, noise_m);
  Points2 points;
  for (int i = 0; i < 720; ++i) {
    const double a = -M_PI + i * 2.0 * M_PI / 720.0;
    const Eigen::Vector2d dir(std::cos(T_world_lidar.yaw + a), std::sin(T_world_lidar.yaw + a));
    const auto range = caster.cast(T_world_lidar.translation(), dir, 0.25, 30.0);
    if (!range) continue;
    const double r = *range + (noise_m > 0.0 ? noise(rng) : 0.0);
    points.push_back(r * Eigen::Vector2d(std::cos(a), std::sin(a)));
  }
  return points;
}

/// A random base pose within +-1.5 m x +-1.2 m of the room's centre, any heading.
SE2 randomBase(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1.5, 1.5), yaw(-M_PI, M_PI);
  const double x = 5.0 + u(rng), y = 4.0 + 0.8 * u(rng);
  return SE2(x, y, yaw(rng));
}

slamprep::algo::IcpParams paramsFromEnvironment() {
  slamprep::algo::IcpParams params;
  if (const char* gate = std::getenv("GATE")) params.outlier_sigmas = std::atof(gate);
  if (const char* trim = std::getenv("TRIM")) params.trim_fraction = std::atof(trim);
  return params;
}

Eigen::Vector3d vec(const SE2& e) {
  return Eigen::Vector3d(e.x, e.y, e.yaw);
}

/// Error of the match (x, y, yaw) in the true current frame, nullopt when it did not converge.
std::optional<Eigen::Vector3d> matchError(const Points2& ref, const Points2& cur,
                                          const SE2& truth) {
  static const slamprep::algo::IcpParams params = paramsFromEnvironment();
  static const bool symmetric = std::getenv("SYM") != nullptr;
  const SE2 guess = truth * SE2(0.005, -0.003, 0.002);
  const auto forward = slamprep::algo::matchPointToLine(ref, cur, guess, params);
  if (!forward.converged) return std::nullopt;
  const Eigen::Vector3d e = vec(between(truth, forward.T_ref_cur));
  if (!symmetric) return e;
  const auto backward = slamprep::algo::matchPointToLine(cur, ref, guess.inverse(), params);
  if (!backward.converged) return std::nullopt;
  return 0.5 * (e + vec(between(truth, backward.T_ref_cur.inverse())));
}

/// Running mean and covariance of pairs of 3-vectors.
struct PairStats {
  int n = 0;
  Eigen::Vector3d sum_a = Eigen::Vector3d::Zero(), sum_b = sum_a, sq_a = sum_a, sq_b = sum_a,
                  cross = sum_a;
  void add(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    ++n;
    sum_a += a, sum_b += b, sq_a += a.cwiseAbs2(), sq_b += b.cwiseAbs2();
    cross += a.cwiseProduct(b);
  }
  Eigen::Vector3d mean() const { return sum_a / n; }
  Eigen::Vector3d sd() const { return (sq_a / n - mean().cwiseAbs2()).cwiseSqrt(); }
  Eigen::Vector3d correlation() const {
    const Eigen::Vector3d ma = sum_a / n, mb = sum_b / n;
    const Eigen::Vector3d va = sq_a / n - ma.cwiseAbs2(), vb = sq_b / n - mb.cwiseAbs2();
    return (cross / n - ma.cwiseProduct(mb)).cwiseQuotient(va.cwiseProduct(vb).cwiseSqrt());
  }
};

void runSingle(const slamprep::sim::PlanarCaster& caster, int draws, const SE2& step,
               const std::string& noisy) {
  std::mt19937_64 rng(7);
  PairStats stats;
  for (int k = 0; k < draws; ++k) {
    const SE2 L0 = randomBase(rng) * kBaseLidar;
    const SE2 L1 = L0 * kBaseLidar.inverse() * step * kBaseLidar;
    const Points2 ref = scan(caster, L0, noisy == "cur" ? 0.0 : kRangeNoiseM, rng);
    const Points2 cur = scan(caster, L1, noisy == "ref" ? 0.0 : kRangeNoiseM, rng);
    if (const auto e = matchError(ref, cur, between(L0, L1))) stats.add(*e, *e);
  }
  const Eigen::Vector3d mean = stats.mean() * 1e3, sd = stats.sd() * 1e3;
  const double root_n = std::sqrt(static_cast<double>(stats.n));
  std::printf(
      "n %d  mean error x %+.4f mm  y %+.4f mm  yaw %+.5f mrad  (standard error %.4f mm, "
      "%.5f mrad)  spread %.3f %.3f mm %.4f mrad\n",
      stats.n, mean.x(), mean.y(), mean.z(), sd.y() / root_n, sd.z() / root_n, sd.x(), sd.y(),
      sd.z());
}

void runChain(const slamprep::sim::PlanarCaster& caster, int draws, const SE2& step) {
  std::mt19937_64 rng(11);
  PairStats stats;
  for (int k = 0; k < draws; ++k) {
    const SE2 L0 = randomBase(rng) * kBaseLidar;
    const SE2 lidar_step = kBaseLidar.inverse() * step * kBaseLidar;
    const SE2 L1 = L0 * lidar_step, L2 = L1 * lidar_step;
    const Points2 a = scan(caster, L0, kRangeNoiseM, rng), b = scan(caster, L1, kRangeNoiseM, rng),
                  c = scan(caster, L2, kRangeNoiseM, rng);
    const auto e1 = matchError(a, b, lidar_step), e2 = matchError(b, c, lidar_step);
    if (e1 && e2) stats.add(*e1, *e2);
  }
  const Eigen::Vector3d rho = stats.correlation();
  std::printf("n %d  consecutive-match error correlation x %+.3f  y %+.3f  yaw %+.3f\n", stats.n,
              rho.x(), rho.y(), rho.z());
}

}  // namespace

int main(int argc, char** argv) {
  const std::filesystem::path root(SLAMPREP_SOURCE_DIR);
  const int draws = argc > 1 ? std::atoi(argv[1]) : 40000;
  const double yaw = argc > 2 ? std::atof(argv[2]) : 0.1;
  const double forward = argc > 3 ? std::atof(argv[3]) : 0.0;
  const std::string noisy = argc > 4 ? argv[4] : "both";
  const slamprep::sim::World world = slamprep::sim::loadWorld(root / "worlds" / "room.yaml");
  const slamprep::sim::PlanarCaster caster(world);
  const SE2 step(forward, 0.0, yaw);  // base motion per scan
  if (noisy == "chain")
    runChain(caster, draws, step);
  else
    runSingle(caster, draws, step, noisy);
  return 0;
}
