#include "slamprep/algo/calibration/combine_recordings.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <limits>

#include "slamprep/algo/calibration/calibration_json.hpp"

namespace slamprep::algo {
namespace {

// The inverse of a positive definite matrix; false when it is not (or sizes differ).
bool invertPositiveDefinite(const Eigen::MatrixXd& C, Eigen::Index m, Eigen::MatrixXd& inverse) {
  if (C.rows() != m || C.cols() != m) return false;
  const Eigen::LLT<Eigen::MatrixXd> llt(C);
  if (llt.info() != Eigen::Success) return false;
  inverse = llt.solve(Eigen::MatrixXd::Identity(m, m));
  return inverse.allFinite();
}

// Eq. (2) per parameter; the worst input and parameter among those beyond the threshold.
void addConsistency(const std::vector<Eigen::VectorXd>& values,
                    const std::vector<Eigen::MatrixXd>& covariances, const CombineParams& params,
                    CombinedEstimate& out) {
  const Eigen::Index m = out.values.size();
  const double n = static_cast<double>(values.size());
  out.chi2_dof = Eigen::VectorXd::Constant(m, std::numeric_limits<double>::quiet_NaN());
  out.sigma_scale = Eigen::VectorXd::Ones(m);
  if (values.size() < 2) return;
  double worst = -1.0;
  for (Eigen::Index j = 0; j < m; ++j) {
    double chi2 = 0.0;
    for (std::size_t i = 0; i < values.size(); ++i) {
      const double d = values[i](j) - out.values(j);
      chi2 += d * d / covariances[i](j, j);
    }
    out.chi2_dof(j) = chi2 / (n - 1.0);
    if (!(out.chi2_dof(j) > params.max_chi2_dof)) continue;
    out.sigma_scale(j) = std::sqrt(out.chi2_dof(j));
    for (std::size_t i = 0; i < values.size(); ++i) {
      const double d = values[i](j) - out.values(j);
      if (d * d / covariances[i](j, j) > worst) {
        worst = d * d / covariances[i](j, j);
        out.worst_input = static_cast<int>(i);
        out.worst_parameter = static_cast<int>(j);
      }
    }
  }
  const Eigen::MatrixXd D = out.sigma_scale.asDiagonal();
  out.covariance = D * out.covariance * D;
}

}  // namespace

CombinedEstimate combineEstimates(const std::vector<Eigen::VectorXd>& values,
                                  const std::vector<Eigen::MatrixXd>& covariances,
                                  const CombineParams& params) {
  CombinedEstimate out;
  if (values.empty() || values.size() != covariances.size()) {
    out.reason = "no estimates to combine";
    return out;
  }
  const Eigen::Index m = values.front().size();
  Eigen::MatrixXd information = Eigen::MatrixXd::Zero(m, m);
  Eigen::VectorXd weighted = Eigen::VectorXd::Zero(m);
  for (std::size_t i = 0; i < values.size(); ++i) {
    Eigen::MatrixXd inverse;
    if (values[i].size() != m || !invertPositiveDefinite(covariances[i], m, inverse)) {
      out.failed_input = static_cast<int>(i);
      out.reason = covariances[i].size() == 0 ? "has no covariance: cannot be weighted"
                                              : "covariance not positive definite";
      return out;
    }
    information += inverse;
    weighted += inverse * values[i];
  }
  Eigen::MatrixXd covariance;
  if (!invertPositiveDefinite(information, m, covariance)) {
    out.reason = "the summed information is singular";
    return out;
  }
  out.covariance = 0.5 * (covariance + covariance.transpose());
  out.values = out.covariance * weighted;  // Eq. (1)
  addConsistency(values, covariances, params, out);
  out.ratio_chi2_dof = ratioConsistency(values, covariances);
  out.ok = true;
  return out;
}

double wheelRatioVariance(const Eigen::VectorXd& x, const Eigen::MatrixXd& C, int wheel) {
  const double r = x(wheel), b = x(2);
  Eigen::Vector3d g = Eigen::Vector3d::Zero();  // Eq. (3): d(r / b) / d(r_L, r_R, b)
  g(wheel) = 1.0 / b;
  g(2) = -r / (b * b);
  return g.dot(C.topLeftCorner<3, 3>() * g);
}

Eigen::Vector2d ratioConsistency(const std::vector<Eigen::VectorXd>& values,
                                 const std::vector<Eigen::MatrixXd>& covariances) {
  Eigen::Vector2d out = Eigen::Vector2d::Constant(std::numeric_limits<double>::quiet_NaN());
  if (values.size() < 2 || values.front().size() < 3) return out;
  const double n = static_cast<double>(values.size());
  for (int wheel = 0; wheel < 2; ++wheel) {
    std::vector<double> q, var;
    for (std::size_t i = 0; i < values.size(); ++i) {
      q.push_back(values[i](wheel) / values[i](2));
      var.push_back(wheelRatioVariance(values[i], covariances[i], wheel));
    }
    if (!std::all_of(var.begin(), var.end(), [](double v) { return v > 0.0; })) continue;
    double weights = 0.0, mean = 0.0;
    for (std::size_t i = 0; i < q.size(); ++i) {
      weights += 1.0 / var[i];
      mean += q[i] / var[i];
    }
    mean /= weights;
    double chi2 = 0.0;
    for (std::size_t i = 0; i < q.size(); ++i) chi2 += (q[i] - mean) * (q[i] - mean) / var[i];
    out(wheel) = chi2 / (n - 1.0);
  }
  return out;
}

namespace {

void fillResult(const CombinedEstimate& e, const std::vector<const CalibrationRun*>& runs,
                const std::vector<int>& used, CalibrationResult& r) {
  const Eigen::VectorXd& v = e.values;
  r.ok = true;
  r.geometry = {v(0), v(1), v(2)};
  if (r.estimates_mount) r.T_base_lidar = SE2{v(3), v(4), normalizeAngle(v(5))};
  r.covariance = e.covariance;
  for (const int i : used) {
    const CalibrationResult& one = runs[i]->result;
    r.condition_number = std::max(r.condition_number, one.condition_number);
    r.intervals_used += one.intervals_used;
    r.intervals_trimmed += one.intervals_trimmed;
  }
}

}  // namespace

CombinedRun combineRuns(CalibrationMethod method, const std::vector<const CalibrationRun*>& runs,
                        const CombineParams& params) {
  CombinedRun out;
  out.run.method = method;
  CalibrationResult& r = out.run.result;
  r.estimates_mount = estimatesMount(method);
  std::vector<Eigen::VectorXd> values;
  std::vector<Eigen::MatrixXd> covariances;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    if (!runs[i] || !runs[i]->result.ok) continue;
    Eigen::VectorXd v = calibrationValues(runs[i]->result);
    if (v.size() == 6 && !values.empty())  // the yaw next to the first one's, not 2 pi away
      v(5) = values.front()(5) + normalizeAngle(v(5) - values.front()(5));
    values.push_back(v);
    covariances.push_back(runs[i]->result.covariance);
    out.recordings.push_back(static_cast<int>(i));
  }
  if (values.empty()) {
    r.reason = "refused in every recording";
    return out;
  }
  out.run.relative_to_odometry = runs[out.recordings.front()]->relative_to_odometry;
  out.estimate = combineEstimates(values, covariances, params);
  if (!out.estimate.ok) {
    const int failed = out.estimate.failed_input;
    r.reason = failed < 0 ? out.estimate.reason
                          : "recording " + std::to_string(out.recordings[failed] + 1) + ": " +
                                out.estimate.reason;
    return out;
  }
  fillResult(out.estimate, runs, out.recordings, r);
  return out;
}

}  // namespace slamprep::algo
