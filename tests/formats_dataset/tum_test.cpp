#include "slamprep/eval/formats/tum.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <numbers>
#include <random>

#include "slamprep/core/error.hpp"

namespace slamprep::eval {
namespace {

using std::numbers::pi;

std::uint64_t bits(double x) {
  return std::bit_cast<std::uint64_t>(x);
}

TEST(Tum, YawQuaternionRecoversEveryYawExactly) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> yaw(-pi, pi);
  std::vector<double> yaws = {0.0,
                              -0.0,
                              pi,
                              std::nextafter(pi, 0.0),
                              -std::nextafter(pi, 0.0),
                              1e-300,
                              -1e-300,
                              1.0,
                              pi / 2,
                              -pi / 2,
                              2.0,
                              1e-8};
  for (int k = 0; k < 200000; ++k) yaws.push_back(SE2(0, 0, yaw(rng)).yaw);
  for (double y : yaws) {
    const YawQuaternion q = yawToQuaternion(y);
    ASSERT_EQ(bits(yawFromQuaternion(0.0, 0.0, q.qz, q.qw)), bits(y)) << y;
    // Nudged by at most 64 ulps of a number <= 1: unit to 1.5e-14.
    ASSERT_NEAR(std::hypot(q.qz, q.qw), 1.0, 1.5e-14) << y;
  }
}

TEST(Tum, YawOfATiltedQuaternionIsTheHeadingOfItsXAxis) {
  // q = q_yaw(0.7) * q_roll(0.4): a roll about x leaves the x axis, so the heading is 0.7.
  const double cy = std::cos(0.35), sy = std::sin(0.35), cr = std::cos(0.2), sr = std::sin(0.2);
  const double qw = cy * cr, qx = cy * sr, qy = sy * sr, qz = sy * cr;
  EXPECT_NEAR(yawFromQuaternion(qx, qy, qz, qw), 0.7, 1e-15);
  // -q is the same rotation.
  EXPECT_NEAR(yawFromQuaternion(-qx, -qy, -qz, -qw), 0.7, 1e-15);
  EXPECT_NEAR(yawFromQuaternion(0, 0, -std::sin(1.5), -std::cos(1.5)), normalizeAngle(3.0), 1e-15);
}

TEST(Tum, ReadsEvoStyleFilesWithCommentsAndTabs) {
  const PoseSeries poses = parseTum(
      "# timestamp tx ty tz qx qy qz qw\n"
      "\n"
      "1.0\t2.0 3.0 0.5 0 0 0.7071067811865476 0.7071067811865476\r\n"
      "  1.5 2.5 3.5 0 0 0 0 1  \n",
      "t.tum");
  ASSERT_EQ(poses.size(), 2u);
  EXPECT_EQ(poses[0].stamp_s, 1.0);
  EXPECT_EQ(poses[0].value.x, 2.0);
  EXPECT_NEAR(poses[0].value.yaw, pi / 2, 1e-15);
  EXPECT_EQ(poses[1].value.yaw, 0.0);
}

void expectError(const std::string& text, const std::string& expected) {
  try {
    parseTum(text, "g.tum");
    ADD_FAILURE() << "accepted: " << text;
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(expected), std::string::npos)
        << e.what() << "\nexpected: " << expected;
  }
}

TEST(Tum, RejectsMalformedLinesNamingLineAndColumn) {
  const std::string ok = "# h\n1 0 0 0 0 0 0 1\n";
  expectError(ok + "2 0 0 0 0 0 1\n", "g.tum:3: expected 8 columns");
  expectError(ok + "2 0 0 0 0 0 0 1 9\n", "g.tum:3: expected 8 columns");
  expectError(ok + "2 0 abc 0 0 0 0 1\n", "g.tum:3: y: not a number");
  expectError(ok + "2 nan 0 0 0 0 0 1\n", "g.tum:3: x: must be finite");
  expectError(ok + "2 0 0 0 0 0 0 inf\n", "g.tum:3: qw: must be finite");
  expectError(ok + "1 0 0 0 0 0 0 1\n", "g.tum:3: t: duplicate timestamp 1 after 1");
  expectError(ok + "0.5 0 0 0 0 0 0 1\n", "g.tum:3: t: timestamp 0.5 after 1");
  expectError(ok + "2 0 0 0 0 0 0 0\n", "g.tum:3: qx qy qz qw: quaternion norm");
  expectError(ok + "2 0 0 0 1 0 0 1\n", "g.tum:3: qx qy qz qw: quaternion norm");
}

TEST(Tum, WriterRefusesWhatTheReaderWouldReject) {
  PoseSeries poses;
  poses.push_back(1.0, SE2(std::nan(""), 0, 0));
  EXPECT_THROW(formatTum(poses, "o.tum"), InputError);
}

}  // namespace
}  // namespace slamprep::eval
