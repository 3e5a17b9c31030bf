// The calibration JSON: written and read back in one place, the best entry by the one rule, and
// errors that name the file and the field.
#include "slamprep/algo/calibration/calibration_json.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "slamprep/core/error.hpp"

namespace slamprep::algo {
namespace {

CalibrationRun okRun(CalibrationMethod method, double scale) {
  CalibrationRun run;
  run.method = method;
  CalibrationResult& r = run.result;
  r.ok = true;
  r.geometry = {0.1 * scale, 0.2 * scale, 0.5 * scale};
  r.estimates_mount = estimatesMount(method);
  if (r.estimates_mount) r.T_base_lidar = SE2(0.1, -0.02, 0.01);
  const int n = r.estimates_mount ? 6 : 3;
  r.covariance = Eigen::MatrixXd::Identity(n, n) * 1e-6;
  r.condition_number = 4.5;
  r.intervals_used = 75;
  return run;
}

std::string message(const std::string& text) {
  try {
    parseCalibrationJson(text, "cal.json");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(CalibrationJson, RoundTripsEveryRunAndPicksTheBest) {
  CalibrationRun refused;
  refused.method = CalibrationMethod::kUmbmark;
  refused.result.reason = "no UMBmark square runs";
  std::vector<CalibrationRun> runs = {okRun(CalibrationMethod::kModel, 1.0),
                                      okRun(CalibrationMethod::kJoint, 1.01),
                                      okRun(CalibrationMethod::kCeres, 1.02), refused};
  runs[1].result.rotation_heteroscedasticity = 32.7;  // residuals grow with the turn
  runs[1].result.sigma_sandwich_factors = {1.0, 1.0, 1.4, 1.0, 1.2, 1.0};
  runs[2].result.rotation_heteroscedasticity = 3.1;  // below the test's threshold: not written
  runs[2].sideslip_s = -6.6e-4;                      // calibrate --sideslip
  runs[2].sideslip_sigma_s = 1.8e-5;
  const CalibrationTruth truth{{0.1, 0.2, 0.5}, SE2(0.1, 0.0, 0.0)};
  const std::string text = formatCalibrationJson(runs, truth);
  const auto j = nlohmann::json::parse(text);
  ASSERT_EQ(j.size(), 4u);
  EXPECT_EQ(j[0]["method"], "model");
  EXPECT_FALSE(j[0].contains("lidar_x"));  // model does not estimate the mount
  EXPECT_EQ(j[2]["lidar_y"].get<double>(), -0.02);
  EXPECT_NEAR(j[1]["error"]["b"].get<double>(), 0.005, 1e-15);
  EXPECT_TRUE(j[3]["r_L"].is_null());
  EXPECT_EQ(j[2]["sideslip_s"]["value"].get<double>(), -6.6e-4);
  EXPECT_EQ(j[2]["sideslip_s"]["sigma"].get<double>(), 1.8e-5);
  EXPECT_FALSE(j[1].contains("sideslip_s"));  // not estimated
  EXPECT_FALSE(j[2].contains("time_offset_s"));
  EXPECT_EQ(j[1]["rotation_heteroscedasticity"].get<double>(), 32.7);
  EXPECT_FALSE(j[2].contains("rotation_heteroscedasticity"));
  EXPECT_EQ(j[1]["sigma_sandwich"], nlohmann::json::parse(R"({"b": 1.4, "lidar_y": 1.2})"));
  EXPECT_FALSE(j[0].contains("sigma_sandwich"));  // none raised: not written

  const CalibrationFile file = parseCalibrationJson(text, "cal.json");
  ASSERT_EQ(file.runs.size(), 4u);
  for (std::size_t i = 0; i < runs.size(); ++i) {
    EXPECT_EQ(file.runs[i].method, runs[i].method);
    EXPECT_EQ(file.runs[i].result.ok, runs[i].result.ok);
    EXPECT_EQ(file.runs[i].result.reason, runs[i].result.reason);
    // nlohmann writes doubles with round-trip precision: the same bits come back.
    EXPECT_EQ(file.runs[i].result.geometry.wheel_base_m, runs[i].result.geometry.wheel_base_m);
    EXPECT_EQ(file.runs[i].result.T_base_lidar.yaw, runs[i].result.T_base_lidar.yaw);
  }
  EXPECT_EQ(file.runs[2].result.sigma()(5), std::sqrt(1e-6));  // sigma is written, not variance
  EXPECT_EQ(file.runs[1].result.intervals_used, 75);
  EXPECT_EQ(file.runs[1].result.sigma_sandwich_factors, runs[1].result.sigma_sandwich_factors);
  EXPECT_EQ(file.runs[1].result.rotation_heteroscedasticity, 32.7);
  EXPECT_EQ(file.runs[0].result.condition_number, 4.5);
  EXPECT_EQ(file.runs[2].sideslip_s, -6.6e-4);
  EXPECT_EQ(file.runs[2].sideslip_sigma_s, 1.8e-5);
  EXPECT_FALSE(file.runs[1].sideslip_s.has_value());
  ASSERT_NE(file.best(), nullptr);
  EXPECT_EQ(file.best()->method, CalibrationMethod::kCeres);
  EXPECT_EQ(file.requireBest().result.geometry.wheel_base_m,
            file.best()->result.geometry.wheel_base_m);
  // Written again from what was read: the same text (the error needs the truth again).
  EXPECT_EQ(formatCalibrationJson(file.runs, truth), text);
}

TEST(CalibrationJson, BestIsTheFirstOkInPreferenceOrder) {
  const CalibrationFile f = parseCalibrationJson(
      R"([{"method":"model","ok":true,"r_L":0.1,"r_R":0.2,"b":0.5},
          {"method":"ceres","ok":true,"r_L":0.11,"r_R":0.21,"b":0.51,
           "lidar_x":0.1,"lidar_y":0.0,"lidar_yaw":0.0},
          {"method":"joint","ok":false,"r_L":null,"r_R":null,"b":null}])",
      "cal.json");
  ASSERT_NE(f.best(), nullptr);
  EXPECT_EQ(f.best()->method, CalibrationMethod::kCeres);
  EXPECT_EQ(f.best()->result.geometry.wheel_base_m, 0.51);
  // One object alone is an array of one.
  const CalibrationFile one =
      parseCalibrationJson(R"({"method":"direct","ok":true,"r_L":0.1,"r_R":0.2,"b":0.5})", "c");
  ASSERT_NE(one.best(), nullptr);
  EXPECT_EQ(one.best()->method, CalibrationMethod::kDirect);
}

TEST(CalibrationJson, ErrorsNameTheFileAndTheField) {
  EXPECT_NE(message(R"([{"method":"model","ok":true,"r_L":-0.1,"r_R":0.2,"b":0.5}])")
                .find("cal.json: [0].r_L"),
            std::string::npos);
  EXPECT_NE(message(R"([{"method":"model","ok":true,"r_L":0.1,"r_R":0.2}])").find("[0].b"),
            std::string::npos);
  EXPECT_NE(
      message(R"([{"method":"joint","ok":true,"r_L":0.1,"r_R":0.2,"b":0.5}])").find("[0].lidar_x"),
      std::string::npos);
  EXPECT_NE(message(R"([{"method":"magic","ok":false}])").find("[0].method"), std::string::npos);
  EXPECT_NE(message(R"([{"method":"model"}])").find("[0].ok"), std::string::npos);
  EXPECT_NE(message(R"([3])").find("[0]"), std::string::npos);
  EXPECT_NE(message(R"([{"method":"model","ok":true,"r_L":0.1)").find("cal.json:1: bad JSON"),
            std::string::npos);
  // A key given twice kept one value silently.
  EXPECT_NE(message(R"([{"method":"model","ok":true,"ok":false}])")
                .find("cal.json:1: key \"ok\" appears twice in one object"),
            std::string::npos);
  EXPECT_NE(message(R"("ceres")").find("cal.json"), std::string::npos);
  const CalibrationFile none = parseCalibrationJson(R"([{"method":"model","ok":false}])", "c.json");
  EXPECT_EQ(none.best(), nullptr);
  EXPECT_THROW(none.requireBest(), InputError);
  EXPECT_THROW(readCalibrationJson("/nonexistent/calibration.json"), InputError);
}

}  // namespace
}  // namespace slamprep::algo
