// Several recordings combined: Eq. (1) and (2) of combine_recordings.hpp against values computed
// by hand, the sigma scaling where the recordings disagree, the runs' bookkeeping, the 15 % flags
// and the JSON of several recordings.
#include "slamprep/algo/calibration/combine_recordings.hpp"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <cmath>
#include <nlohmann/json.hpp>
#include <numbers>
#include <random>

#include "slamprep/algo/calibration/calibration_json.hpp"
#include "slamprep/algo/calibration/nominal_flags.hpp"

namespace slamprep::algo {
namespace {

Eigen::VectorXd vec(std::initializer_list<double> v) {
  Eigen::VectorXd out(static_cast<Eigen::Index>(v.size()));
  Eigen::Index i = 0;
  for (const double x : v) out(i++) = x;
  return out;
}

Eigen::MatrixXd diag(std::initializer_list<double> sigmas) {
  const Eigen::VectorXd s = vec(sigmas);
  return s.cwiseProduct(s).asDiagonal();
}

CalibrationRun run(CalibrationMethod method, const Eigen::VectorXd& v, const Eigen::MatrixXd& C) {
  CalibrationRun out;
  out.method = method;
  out.result.ok = true;
  out.result.estimates_mount = v.size() == 6;
  out.result.geometry = {v(0), v(1), v(2)};
  if (v.size() == 6) out.result.T_base_lidar = SE2(v(3), v(4), v(5));
  out.result.covariance = C;
  out.result.intervals_used = 100;
  out.result.condition_number = 10.0;
  return out;
}

// Two consistent recordings, diagonal covariances. By hand: r_L weights 1e6 and 2.5e5 give
// (1e5 + 25750) / 1.25e6 = 0.1006 and chi2 = 0.36 + 1.44 = 1.8; r_R equal weights 0.09925,
// chi2 = 2 * 0.5625; b weights 1e4 and 2500 give 6300 / 12500 = 0.504, chi2 = 0.16 + 0.64.
TEST(CombineRecordings, TwoConsistentRecordingsByHand) {
  const CombinedEstimate c =
      combineEstimates({vec({0.100, 0.100, 0.500}), vec({0.103, 0.0985, 0.520})},
                       {diag({0.001, 0.001, 0.01}), diag({0.002, 0.001, 0.02})});
  ASSERT_TRUE(c.ok) << c.reason;
  EXPECT_NEAR(c.values(0), 0.1006, 1e-14);
  EXPECT_NEAR(c.values(1), 0.09925, 1e-14);
  EXPECT_NEAR(c.values(2), 0.504, 1e-14);
  EXPECT_NEAR(c.chi2_dof(0), 1.8, 1e-9);
  EXPECT_NEAR(c.chi2_dof(1), 1.125, 1e-9);
  EXPECT_NEAR(c.chi2_dof(2), 0.8, 1e-9);
  // Nothing beyond 2: the sigmas are the information's, sqrt(1 / 1.25e6) etc.
  EXPECT_NEAR(std::sqrt(c.covariance(0, 0)), std::sqrt(1.0 / 1.25e6), 1e-15);
  EXPECT_NEAR(std::sqrt(c.covariance(2, 2)), std::sqrt(1.0 / 12500.0), 1e-15);
  EXPECT_EQ(c.sigma_scale, Eigen::VectorXd::Ones(3));
  EXPECT_EQ(c.worst_input, -1);
}

// Full covariances: C1 = [[4, 1], [1, 2]] 1e-6, C2 = [[1, -0.5], [-0.5, 3]] 1e-6. By hand
// C1^-1 = [[2, -1], [-1, 4]] / 7e6, C2^-1 = [[12, 2], [2, 4]] / 11e6, their sum
// [[106, 3], [3, 72]] / 77e6, whose inverse is [[8/11, -1/33], [-1/33, 106/99]] 1e-6.
TEST(CombineRecordings, FullCovariancesByHand) {
  Eigen::MatrixXd C1(2, 2), C2(2, 2);
  C1 << 4e-6, 1e-6, 1e-6, 2e-6;
  C2 << 1e-6, -0.5e-6, -0.5e-6, 3e-6;
  const Eigen::VectorXd x1 = vec({0.100, 0.500}), x2 = vec({0.102, 0.497});
  const CombinedEstimate c = combineEstimates({x1, x2}, {C1, C2});
  ASSERT_TRUE(c.ok) << c.reason;
  EXPECT_NEAR(c.covariance(0, 0), 8.0 / 11.0 * 1e-6, 1e-18);
  EXPECT_NEAR(c.covariance(0, 1), -1.0 / 33.0 * 1e-6, 1e-18);
  EXPECT_NEAR(c.covariance(1, 1), 106.0 / 99.0 * 1e-6, 1e-18);
  // x = C (C1^-1 x1 + C2^-1 x2)
  const Eigen::Vector2d expected = c.covariance * (C1.inverse() * x1 + C2.inverse() * x2);
  EXPECT_NEAR(c.values(0), expected(0), 1e-14);
  EXPECT_NEAR(c.values(0), 0.10121212121212121, 1e-12);
  EXPECT_NEAR(c.values(1), 0.49917171717171717, 1e-12);
  // Not the diagonal-weighted mean: the correlation moves it.
  EXPECT_GT(std::abs(c.values(0) - (0.100 / 4 + 0.102 / 1) / (1.0 / 4 + 1.0)), 1e-4);
}

// The TurtleBot of the brief: b = 180 +- 5.6, 294 +- 27, 261 +- 15 mm. By hand the weighted
// mean is 193.70 mm, sigma 5.15 mm, chi2/dof 19.96: the sigma grows to 23.0 mm and the third
// recording (normalised square deviation 20.1) is the worst.
TEST(CombineRecordings, ThreeInconsistentRecordingsScaleTheSigma) {
  const CombinedEstimate c = combineEstimates(
      {vec({0.033, 0.033, 0.180}), vec({0.033, 0.033, 0.294}), vec({0.033, 0.033, 0.261})},
      {diag({1e-4, 1e-4, 0.0056}), diag({1e-4, 1e-4, 0.027}), diag({1e-4, 1e-4, 0.015})});
  ASSERT_TRUE(c.ok) << c.reason;
  EXPECT_NEAR(c.values(2), 0.19369561319327527, 1e-12);
  EXPECT_NEAR(c.chi2_dof(2), 19.95751945783502, 1e-8);
  EXPECT_NEAR(c.sigma_scale(2), std::sqrt(19.95751945783502), 1e-8);
  EXPECT_NEAR(std::sqrt(c.covariance(2, 2)), 0.023006995275564036, 1e-12);
  EXPECT_EQ(c.chi2_dof(0), 0.0);  // identical radii: perfectly consistent, not scaled
  EXPECT_EQ(c.sigma_scale(0), 1.0);
  EXPECT_EQ(c.worst_input, 2);
  EXPECT_EQ(c.worst_parameter, 2);
}

TEST(CombineRecordings, TwoInconsistentRecordings) {
  // b = 180 +- 5.6 and 294 +- 27 mm: weights 1/5.6^2 and 1/27^2, chi2 with n - 1 = 1.
  const double w1 = 1.0 / (0.0056 * 0.0056), w2 = 1.0 / (0.027 * 0.027);
  const double mean = (w1 * 0.180 + w2 * 0.294) / (w1 + w2);
  const double chi2 = w1 * (0.180 - mean) * (0.180 - mean) + w2 * (0.294 - mean) * (0.294 - mean);
  EXPECT_NEAR(mean, 0.1847017728444421, 1e-15);  // 184.7 mm, chi2/dof 17.1
  EXPECT_NEAR(chi2, 17.091903835025512, 1e-9);
  const CombinedEstimate c =
      combineEstimates({vec({0.180}), vec({0.294})}, {diag({0.0056}), diag({0.027})});
  ASSERT_TRUE(c.ok);
  EXPECT_NEAR(c.values(0), mean, 1e-14);
  EXPECT_NEAR(c.chi2_dof(0), chi2, 1e-9);
  EXPECT_GT(c.chi2_dof(0), 2.0);
  EXPECT_NEAR(std::sqrt(c.covariance(0, 0)), std::sqrt(chi2 / (w1 + w2)), 1e-12);
  EXPECT_EQ(c.worst_parameter, 0);
}

// Eq. (3) by hand: b known (sigma 1 nm), r_L 0.100 and 0.102 m +- 1 mm over b 0.5 m: q_L = 0.200
// and 0.204, each +- 0.002, mean 0.202, chi2 = 1 + 1 with n - 1 = 1; r_R the same in both: 0.
TEST(CombineRecordings, RatioConsistencyByHand) {
  const Eigen::Vector2d chi2 =
      ratioConsistency({vec({0.100, 0.100, 0.5}), vec({0.102, 0.100, 0.5})},
                       {diag({0.001, 0.001, 1e-9}), diag({0.001, 0.001, 1e-9})});
  EXPECT_NEAR(chi2(0), 2.0, 1e-6);
  EXPECT_NEAR(chi2(1), 0.0, 1e-12);
  EXPECT_TRUE(std::isnan(ratioConsistency({vec({0.1, 0.1, 0.5})}, {diag({1e-3, 1e-3, 1e-3})})(0)));
}

// Two recordings whose r and b are 99 % correlated (a drive pins r / b down, not r or b): each
// of r_L, r_R and b agrees within 1.5 sigma, r / b is 5 % apart at sigmas under 1 %. Eq. (3)
// says so; its variance checked against the ratio's spread over samples of each covariance.
TEST(CombineRecordings, RatiosDisagreeWhereREachAndBEachAgree) {
  auto correlated = [](double sr, double sb) {
    Eigen::MatrixXd C(3, 3);
    C << sr * sr, 0.98 * sr * sr, 0.99 * sr * sb, 0.98 * sr * sr, sr * sr, 0.99 * sr * sb,
        0.99 * sr * sb, 0.99 * sr * sb, sb * sb;
    return C;
  };
  const std::vector<Eigen::VectorXd> x = {vec({0.0354, 0.0354, 0.2372}),
                                          vec({0.0357, 0.0358, 0.2530})};
  const std::vector<Eigen::MatrixXd> C = {correlated(0.0010, 0.0068), correlated(0.0016, 0.0111)};
  const Eigen::Vector2d chi2 = ratioConsistency(x, C);
  EXPECT_GT(chi2(0), 10.0);
  EXPECT_GT(chi2(1), 10.0);
  const CombinedEstimate c = combineEstimates(x, C);
  ASSERT_TRUE(c.ok) << c.reason;
  EXPECT_EQ(c.ratio_chi2_dof, chi2);
  for (int j = 0; j < 3; ++j)  // each difference within 1.5 sigma of the difference
    EXPECT_LT(std::abs(x[0](j) - x[1](j)), 1.5 * std::sqrt(C[0](j, j) + C[1](j, j)));
  // Brute force: the ratio's variance over samples of recording 1's covariance.
  std::mt19937 rng(7);
  std::normal_distribution<double> n01;
  const Eigen::MatrixXd L = Eigen::LLT<Eigen::MatrixXd>(C[0]).matrixL();
  double sum = 0.0, sum2 = 0.0;
  const int samples = 200000;
  for (int k = 0; k < samples; ++k) {
    Eigen::Vector3d z(n01(rng), n01(rng), n01(rng));
    const Eigen::Vector3d s = x[0] + L * z;
    sum += s(0) / s(2);
    sum2 += s(0) / s(2) * s(0) / s(2);
  }
  const double var_sampled = sum2 / samples - (sum / samples) * (sum / samples);
  EXPECT_NEAR(std::sqrt(wheelRatioVariance(x[0], C[0], 0)), std::sqrt(var_sampled),
              0.05 * std::sqrt(var_sampled));
}

TEST(CombineRecordings, RefusesWhatCannotBeWeighted) {
  EXPECT_FALSE(combineEstimates({}, {}).ok);
  const CombinedEstimate none =
      combineEstimates({vec({1.0}), vec({1.0})}, {diag({0.1}), Eigen::MatrixXd()});
  EXPECT_FALSE(none.ok);
  EXPECT_EQ(none.failed_input, 1);
  EXPECT_NE(none.reason.find("no covariance"), std::string::npos);
  Eigen::MatrixXd indefinite(1, 1);
  indefinite << -1.0;
  EXPECT_FALSE(combineEstimates({vec({1.0})}, {indefinite}).ok);
}

TEST(CombineRuns, SkipsRefusedRunsAndUnwrapsTheYaw) {
  const double pi = std::numbers::pi;
  const CalibrationRun a = run(CalibrationMethod::kJoint, vec({0.1, 0.1, 0.5, 0.1, 0.0, pi - 0.01}),
                               diag({1e-3, 1e-3, 1e-3, 1e-3, 1e-3, 0.01}));
  const CalibrationRun b =
      run(CalibrationMethod::kJoint, vec({0.1, 0.1, 0.5, 0.1, 0.0, -pi + 0.01}),
          diag({1e-3, 1e-3, 1e-3, 1e-3, 1e-3, 0.01}));
  CalibrationRun refused;
  refused.method = CalibrationMethod::kJoint;
  refused.result.reason = "too few intervals";
  const CombinedRun c = combineRuns(CalibrationMethod::kJoint, {&a, &refused, nullptr, &b});
  ASSERT_TRUE(c.run.result.ok) << c.run.result.reason;
  EXPECT_EQ(c.recordings, (std::vector<int>{0, 3}));
  // pi - 0.01 and -pi + 0.01 average to pi, not 0.
  EXPECT_NEAR(std::abs(c.run.result.T_base_lidar.yaw), pi, 1e-12);
  EXPECT_NEAR(c.estimate.chi2_dof(5), 2.0 * 0.01 * 0.01 / (0.01 * 0.01), 1e-9);
  EXPECT_EQ(c.run.result.intervals_used, 200);
  const CombinedRun none = combineRuns(CalibrationMethod::kJoint, {&refused, nullptr});
  EXPECT_FALSE(none.run.result.ok);
  EXPECT_EQ(none.run.result.reason, "refused in every recording");
}

TEST(NominalFlags, FifteenPercentWithTheLikelyCause) {
  const DiffDriveParams nominal{0.033, 0.033, 0.160};
  CalibrationResult r;
  r.ok = true;
  r.geometry = {0.033 * 1.01, 0.033 * 0.99, 0.160 * 1.14};  // within 15 %: nothing
  EXPECT_TRUE(nominalFlags(r, nominal).empty());
  r.geometry.wheel_base_m = 0.294;  // the TurtleBot's second recording: b 1.84 x nominal
  auto flags = nominalFlags(r, nominal);
  ASSERT_EQ(flags.size(), 1u);
  EXPECT_EQ(flags[0].param, "b");
  EXPECT_NEAR(flags[0].ratio, 0.294 / 0.160, 1e-15);
  EXPECT_NE(flags[0].likely_cause.find("rotation from the scans and the wheels disagree"),
            std::string::npos);
  r.geometry = {0.033 * 1.2, 0.033 * 1.25, 0.160};  // radii off together
  flags = nominalFlags(r, nominal);
  ASSERT_EQ(flags.size(), 2u);
  EXPECT_EQ(flags[1].param, "r_R");
  EXPECT_NE(flags[0].likely_cause.find("translation"), std::string::npos);
  r.geometry = {0.033 * 0.8, 0.033, 0.160};  // one wheel
  flags = nominalFlags(r, nominal);
  ASSERT_EQ(flags.size(), 1u);
  EXPECT_NE(flags[0].likely_cause.find("the two wheels disagree"), std::string::npos);
  r.ok = false;  // a refused result has no numbers to flag
  EXPECT_TRUE(nominalFlags(r, nominal).empty());
}

// One recording: today's array, byte for byte; several: recordings, combined, consistency, and
// the combined methods are what --calibration reads.
TEST(CalibrateJson, OneRecordingIsTodaysArraySeveralTheCombinedObject) {
  const CalibrationRun a =
      run(CalibrationMethod::kModel, vec({0.1, 0.1, 0.5}), diag({1e-4, 1e-4, 1e-3}));
  const CalibrationRun b =
      run(CalibrationMethod::kModel, vec({0.1, 0.1, 0.6}), diag({1e-4, 1e-4, 1e-3}));
  RecordingReport one{"a", {{a, {}, std::nullopt, std::nullopt}}, std::nullopt, std::nullopt, ""};
  EXPECT_EQ(formatCalibrateJson({{one}, {}, std::nullopt, {}, {}}),
            formatCalibrationJson({a}, std::nullopt));
  EXPECT_EQ(formatCalibrationJson({a}, std::nullopt).front(), '[');
  // With the sensor agreement: the clock sync beside it, in every method object.
  RecordingReport synced{
      "a", {{a, {}, std::nullopt, std::nullopt}}, std::nullopt, SensorAgreement{}, "", 0.17};
  const auto s = nlohmann::json::parse(formatCalibrateJson({{synced}, {}, std::nullopt, {}, {}}));
  EXPECT_EQ(s[0]["clock_sync_s"].get<double>(), 0.17);
  EXPECT_TRUE(s[0].contains("sensor_agreement"));

  const CombinedRun c = combineRuns(CalibrationMethod::kModel, {&a, &b});
  RecordingReport two{"b",
                      {{b, nominalFlags(b.result, {0.1, 0.1, 0.5}), std::nullopt,
                        nominalTest(b.result, {0.1, 0.1, 0.5})}},
                      std::nullopt,
                      std::nullopt,
                      ""};
  MethodReport combined{c.run,
                        {},
                        ValidationFigures{0.2, {0.5, 3.0}, {0.05, 0.3}, HeldOutError{0.04, 0.3}},
                        std::nullopt};
  const CalibrateReport report{
      {one, two},
      {combined},
      std::nullopt,
      {{CalibrationMethod::kModel,
        {{"r_L", c.estimate.chi2_dof(0), 2}, {"b", c.estimate.chi2_dof(2), 2}}}},
      {}};
  const auto j = nlohmann::json::parse(formatCalibrateJson(report));
  ASSERT_TRUE(j.is_object());
  EXPECT_EQ(j.size(), 3u);
  EXPECT_EQ(j["recordings"][1]["dataset"], "b");
  EXPECT_EQ(j["recordings"][1]["methods"][0]["flags"][0]["param"], "b");
  EXPECT_DOUBLE_EQ(j["recordings"][1]["methods"][0]["flags"][0]["ratio"].get<double>(), 1.2);
  EXPECT_FALSE(j["recordings"][0]["methods"][0].contains("flags"));  // none: not written
  // b 0.6 against 0.5 with a sigma of 1 mm: z = 100, chi2 = 1e4 (the radii on the nominal).
  const auto& against = j["recordings"][1]["methods"][0]["against_nominal"];
  EXPECT_NEAR(against["chi2"].get<double>(), 1e4, 1e-6);
  EXPECT_EQ(against["dof"], 3);
  EXPECT_EQ(against["p"].get<double>(), chi2Survival3(1e4));
  EXPECT_NEAR(against["z"]["b"].get<double>(), 100.0, 1e-9);
  EXPECT_EQ(against["z"]["r_L"].get<double>(), 0.0);
  EXPECT_EQ(against["shows_nominal_wrong"], true);
  EXPECT_FALSE(j["recordings"][0]["methods"][0].contains("against_nominal"));  // none given
  EXPECT_EQ(j["combined"][0]["method"], "model");
  EXPECT_DOUBLE_EQ(j["combined"][0]["b"].get<double>(), 0.55);
  EXPECT_DOUBLE_EQ(j["combined"][0]["validation"]["calibrated"]["trans_m"].get<double>(), 0.05);
  EXPECT_DOUBLE_EQ(j["combined"][0]["validation"]["calibrated_wheels"]["trans_m"].get<double>(),
                   0.04);
  // b = 0.5 and 0.6, sigma 1 mm each: chi2/dof = 2 (0.05 / 0.001)^2 = 5000.
  EXPECT_NEAR(j["consistency"]["model"]["b"]["chi2_dof"].get<double>(), 5000.0, 1e-9);
  EXPECT_EQ(j["consistency"]["model"]["b"]["n"], 2);
  // sqrt(5000) x the information's sigma sqrt(1e-6 / 2): 0.05, the scatter itself.
  EXPECT_NEAR(j["combined"][0]["sigma"]["b"].get<double>(), 0.05, 1e-15);
  const CalibrationFile file = parseCalibrationJson(formatCalibrateJson(report), "cal.json");
  ASSERT_EQ(file.runs.size(), 1u);
  EXPECT_DOUBLE_EQ(file.requireBest().result.geometry.wheel_base_m, 0.55);
  EXPECT_FALSE(j.contains("leave_one_out"));  // only with --leave-one-out

  // --leave-one-out: one recording scored (better in translation, worse in rotation), one not.
  CalibrateReport loo = report;
  loo.leave_one_out = {{CalibrationMethod::kModel,
                        {{"a", 1, ValidationFigures{1.0, {0.5, 3.0}, {0.1, 3.5}, std::nullopt}, ""},
                         {"b", 0, std::nullopt, "not scored: the other recordings give none"}}}};
  const auto l = nlohmann::json::parse(formatCalibrateJson(loo))["leave_one_out"]["model"];
  EXPECT_EQ(l["recordings"][0]["dataset"], "a");
  EXPECT_EQ(l["recordings"][0]["others"], 1);
  EXPECT_DOUBLE_EQ(l["recordings"][0]["calibrated"]["rot_deg"].get<double>(), 3.5);
  EXPECT_FALSE(l["recordings"][0].contains("fraction"));  // always the whole recording
  EXPECT_EQ(l["recordings"][1]["note"], "not scored: the other recordings give none");
  EXPECT_FALSE(l["recordings"][1].contains("raw"));
  EXPECT_EQ(l["beats_raw"], nlohmann::json({{"trans", 1}, {"rot", 0}, {"scored", 1}}));
}

}  // namespace
}  // namespace slamprep::algo
