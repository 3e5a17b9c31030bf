#include "slamprep/eval/formats/scan_jsonl.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>

#include "slamprep/core/error.hpp"

namespace slamprep::eval {
namespace {

const double kInf = std::numeric_limits<double>::infinity();

ScanRecord smallRecord() {
  ScanRecord r;
  r.scan.stamp_s = 12.345678;
  r.scan.angle_min_rad = -0.5;
  r.scan.angle_increment_rad = 0.25;
  r.scan.time_increment_s = 0.001;
  r.scan.scan_time_s = 0.1;
  r.scan.range_min_m = 0.2;
  r.scan.range_max_m = 10.0;
  r.scan.ranges_m = {1.0, kInf, 0.1, 3.5, 12.0};
  r.T_odom_base_nominal = SE2(1, 2, 0.5);
  r.T_world_base_true = SE2(1.1, 2.1, 0.4);
  r.p_ref_true = {Eigen::Vector2d(0.9, -0.5), std::nullopt, Eigen::Vector2d(0.1, 0.0),
                  Eigen::Vector2d(3, 0.1), Eigen::Vector2d(12, 1)};
  return r;
}

std::string line(const ScanRecord& r) {
  std::string out;
  appendScanLine(out, r, {"s.jsonl", 1});
  return out;
}

TEST(ScanJsonl, WritesCsmLaserDataFields) {
  const nlohmann::json j = nlohmann::json::parse(line(smallRecord()));
  EXPECT_EQ(j["nrays"], 5);
  EXPECT_EQ(j["min_theta"], -0.5);
  EXPECT_EQ(j["max_theta"], 0.5);
  EXPECT_EQ(j["theta"][2], 0.0);
  EXPECT_TRUE(j["readings"][1].is_null());
  // valid: finite and inside [range_min, range_max]; 0.1 < 0.2 and 12 > 10 are invalid.
  EXPECT_EQ(j["valid"], nlohmann::json({1, 0, 0, 1, 0}));
  EXPECT_EQ(j["timestamp"], nlohmann::json({12, 345678}));
  EXPECT_EQ(j["odometry"], nlohmann::json({1.0, 2.0, 0.5}));
  EXPECT_EQ(j["true_pose"][2], 0.4);
  EXPECT_EQ(j["stamp_s"], 12.345678);
  EXPECT_TRUE(j["p_ref_true"][1].is_null());
  EXPECT_EQ(j["p_ref_true"][0], nlohmann::json({0.9, -0.5}));
}

TEST(ScanJsonl, RoundTripKeepsOutOfRangeReadingsAndInfiniteRangeMax) {
  ScanRecord r = smallRecord();
  r.scan.range_max_m = kInf;
  const ScanRecord back = parseScanLine(line(r), {"s.jsonl", 1});
  ASSERT_EQ(back.scan.ranges_m.size(), 5u);
  EXPECT_EQ(back.scan.ranges_m[2], 0.1);  // below range_min: kept, still invalid
  EXPECT_EQ(back.scan.ranges_m[1], kInf);
  EXPECT_EQ(back.scan.range_max_m, kInf);
  EXPECT_EQ(back.scan.time_increment_s, 0.001);
  EXPECT_FALSE(back.p_ref_true[1].has_value());
  EXPECT_EQ(*back.p_ref_true[3], Eigen::Vector2d(3, 0.1));
}

TEST(ScanJsonl, NonFiniteRangesAllReadBackAsNoReturn) {
  ScanRecord r = smallRecord();
  r.scan.ranges_m[0] = -kInf;  // REP 117 "too close"
  r.scan.ranges_m[3] = std::nan("");
  r.p_ref_true.clear();
  r.T_world_base_true.reset();
  const ScanRecord back = parseScanLine(line(r), {"s.jsonl", 1});
  EXPECT_EQ(back.scan.ranges_m[0], kInf);
  EXPECT_EQ(back.scan.ranges_m[3], kInf);
  EXPECT_TRUE(back.p_ref_true.empty());
  EXPECT_FALSE(back.T_world_base_true.has_value());
}

TEST(ScanJsonl, ReadsPlainCsmLinesWithoutSlamprepFields) {
  // CSM's own output: no stamp_s/angle_min; odometry unknown (NaN written as null).
  const ScanRecord r = parseScanLine(
      R"({"nrays":3,"min_theta":-1,"max_theta":1,"readings":[1,null,2.5],"valid":[1,0,0],)"
      R"("theta":[-1,0,1],"timestamp":[100,250000],"odometry":[null,null,null]})",
      {"c.jsonl", 1});
  EXPECT_DOUBLE_EQ(r.scan.stamp_s, 100.25);
  EXPECT_EQ(r.scan.angle_min_rad, -1.0);
  EXPECT_EQ(r.scan.angle_increment_rad, 1.0);
  EXPECT_EQ(r.scan.ranges_m[0], 1.0);
  EXPECT_EQ(r.scan.ranges_m[2], kInf);  // CSM says invalid: honoured
  EXPECT_EQ(r.scan.time_increment_s, 0.0);
  EXPECT_FALSE(r.T_odom_base_nominal.has_value());
}

void expectScanError(const std::string& text, const std::string& expected) {
  try {
    parseScanLine(text, {"s.jsonl", 7});
    ADD_FAILURE() << "accepted: " << text;
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(expected), std::string::npos)
        << e.what() << "\nexpected: " << expected;
  }
}

TEST(ScanJsonl, RejectsMalformedLinesNamingTheField) {
  const std::string head = R"({"stamp_s":1,"angle_min":0,"angle_increment":0.1,)";
  expectScanError("{\"nrays\":2,", "s.jsonl:7: bad JSON");
  expectScanError("[1,2]", "s.jsonl:7: expected a JSON object");
  expectScanError(head + R"("readings":[1,2]})", "s.jsonl:7: nrays: missing required key");
  expectScanError(head + R"("nrays":-1,"readings":[]})",
                  "s.jsonl:7: nrays: expected a non-negative");
  expectScanError(head + R"("nrays":2.5,"readings":[]})",
                  "s.jsonl:7: nrays: expected a non-negative");
  expectScanError(head + R"("nrays":3,"readings":[1,2]})",
                  "s.jsonl:7: readings: has 2 entries but nrays is 3");
  expectScanError(head + R"("nrays":2})", "s.jsonl:7: readings: missing required key");
  expectScanError(head + R"("nrays":2,"readings":[1,"x"]})",
                  "s.jsonl:7: readings[1]: expected a number");
  expectScanError(head + R"("nrays":2,"readings":[1,2],"valid":[1]})",
                  "s.jsonl:7: valid: has 1 entries but nrays is 2");
  expectScanError(head + R"("nrays":2,"readings":[1,null],"valid":[1,1]})",
                  "s.jsonl:7: valid[1]: is 1 but readings[i] is null");
  expectScanError(head + R"("nrays":2,"readings":[1,2],"valid":[1,2]})",
                  "s.jsonl:7: valid[1]: expected 0 or 1");
  expectScanError(head + R"("nrays":2,"readings":[1,2],"theta":[0]})", "s.jsonl:7: theta: has 1");
  expectScanError(head + R"("nrays":2,"readings":[1,2],"p_ref_true":[[1,2]]})",
                  "s.jsonl:7: p_ref_true: has 1 entries but nrays is 2");
  expectScanError(head + R"("nrays":1,"readings":[1],"p_ref_true":[[1]]})",
                  "s.jsonl:7: p_ref_true[0]: expected [x, y] or null");
  expectScanError(head + R"("nrays":1,"readings":[1],"odometry":[1,2]})",
                  "s.jsonl:7: odometry: expected [x, y, th]");
  expectScanError(head + R"("nrays":1,"readings":[1e999]})", "s.jsonl:7: bad JSON");
  expectScanError(R"({"angle_min":0,"angle_increment":0.1,"nrays":1,"readings":[1]})",
                  "s.jsonl:7: stamp_s: missing required key");
  expectScanError(R"({"stamp_s":1,"angle_increment":0.1,"nrays":1,"readings":[1]})",
                  "s.jsonl:7: min_theta: missing required key");
  expectScanError(R"({"stamp_s":"1","angle_min":0,"angle_increment":0.1,"nrays":1,"readings":[1]})",
                  "s.jsonl:7: stamp_s: expected a number, got string");
}

TEST(ScanJsonl, ParseScansChecksOrderAcrossLines) {
  ScanRecord a = smallRecord(), b = smallRecord();
  b.scan.stamp_s = a.scan.stamp_s;
  const std::string text = line(a) + "\n" + line(b);
  try {
    parseScans(text, "s.jsonl");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("s.jsonl:3: stamp_s: duplicate timestamp"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(formatScans({a, b}, "s.jsonl"), InputError);
}

TEST(ScanJsonl, WriterRefusesUnreadableValues) {
  ScanRecord r = smallRecord();
  r.p_ref_true.pop_back();
  EXPECT_THROW(line(r), InputError);
  r = smallRecord();
  r.T_world_base_true = SE2(NAN, 0, 0);
  EXPECT_THROW(line(r), InputError);
  r = smallRecord();
  r.scan.stamp_s = kInf;
  EXPECT_THROW(line(r), InputError);
}

// Scans no algorithm can use, refused on reading (a file from another tool) and on writing (so
// writeDataset never publishes what readDataset refuses). Each check was once missing.
TEST(ScanJsonl, RefusesEmptyScansNegativeRangeMinAndBackwardTime) {
  const std::string head = R"({"stamp_s":1,"angle_min":0,"angle_increment":0.1,)";
  expectScanError(head + R"("nrays":0,"readings":[]})", "s.jsonl:7: nrays: an empty scan");
  expectScanError(head + R"("nrays":1,"readings":[1],"range_min":-1})",
                  "s.jsonl:7: range_min: must not be negative");
  expectScanError(head + R"("nrays":1,"readings":[1],"range_min":2,"range_max":2})",
                  "s.jsonl:7: range_max: must be greater than range_min");
  expectScanError(head + R"("nrays":1,"readings":[1],"time_increment":-0.001})",
                  "s.jsonl:7: time_increment: must not be negative");
  expectScanError(head + R"("nrays":1,"readings":[1],"scan_time":-0.1})",
                  "s.jsonl:7: scan_time: must not be negative");
  // A single beam with range_min 0 and no range_max (unlimited) is fine.
  EXPECT_NO_THROW(parseScanLine(head + R"("nrays":1,"readings":[1],"range_min":0})", {"s", 1}));

  // An increment of 0 or 1e300, a negative reading and a repeated key were read as
  // given (beams on one ray, turning no real way, a distance below zero, one key ignored).
  expectScanError(R"({"stamp_s":1,"angle_min":0,"angle_increment":0,"nrays":3,"readings":[1,1,1]})",
                  "s.jsonl:7: angle_increment: puts all 3 beams at one angle");
  expectScanError(
      R"({"stamp_s":1,"angle_min":0,"angle_increment":1e300,"nrays":2,"readings":[1,1]})",
      "s.jsonl:7: angle_increment: the beams span more than one revolution");
  expectScanError(R"({"stamp_s":1,"min_theta":0,"max_theta":100,"nrays":3,"readings":[1,1,1]})",
                  "s.jsonl:7: max_theta: the beams span more than one revolution");
  expectScanError(
      R"({"stamp_s":1,"angle_min":1e300,"angle_increment":0.1,"nrays":1,"readings":[1]})",
      "s.jsonl:7: angle_min: more than one revolution (2 pi) from 0");
  expectScanError(head + R"("nrays":2,"readings":[1,-2]})",
                  "s.jsonl:7: readings[1]: must not be negative (null: no return)");
  expectScanError(head + R"("nrays":1,"readings":[1],"nrays":2})",
                  "s.jsonl:7: key \"nrays\" appears twice in one object");
  // A full turn to the last beam is fine: 361 beams of 1 degree from -pi to pi.
  std::string full = R"({"stamp_s":1,"angle_min":-3.141592653589793,"angle_increment":)" +
                     std::to_string(3.141592653589793 / 180) + R"(,"nrays":361,"readings":[1)";
  for (int i = 0; i < 360; ++i) full += ",1";
  EXPECT_NO_THROW(parseScanLine(full + "]}", {"s", 1}));

  auto refusedOnWrite = [](auto change, const char* field) {
    ScanRecord r = smallRecord();
    change(r);
    try {
      line(r);
      ADD_FAILURE() << "wrote a scan with a bad " << field;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(std::string("s.jsonl:1: ") + field), std::string::npos)
          << e.what();
    }
  };
  refusedOnWrite(
      [](ScanRecord& r) {
        r.scan.ranges_m.clear();
        r.p_ref_true.clear();
      },
      "nrays");
  refusedOnWrite([](ScanRecord& r) { r.scan.range_min_m = -0.1; }, "range_min");
  refusedOnWrite([](ScanRecord& r) { r.scan.range_max_m = 0.1; }, "range_max");
  refusedOnWrite([](ScanRecord& r) { r.scan.time_increment_s = -1e-4; }, "time_increment");
}

}  // namespace
}  // namespace slamprep::eval
