#include "slamprep/eval/formats/csv_logs.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "slamprep/core/error.hpp"

namespace slamprep::eval {
namespace {

template <typename Parse>
void expectError(Parse parse, const std::string& text, const std::string& expected) {
  try {
    parse(text, "log.csv");
    ADD_FAILURE() << "accepted: " << text;
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(expected), std::string::npos)
        << e.what() << "\nexpected: " << expected;
  }
}

TEST(CsvLogs, EncodersRoundTripAndToleratesCrLfAndBlankLines) {
  EncoderLog log = {{0.5, -3, 9223372036854775807}, {0.75, 0, -4}};
  const std::string text = formatEncoders(log, "e.csv");
  EXPECT_EQ(text, "stamp_s,ticks_left,ticks_right\n0.5,-3,9223372036854775807\n0.75,0,-4\n");
  EncoderLog back = parseEncoders(text, "e.csv");
  ASSERT_EQ(back.size(), 2u);
  EXPECT_EQ(back[0].ticks_right, 9223372036854775807);
  EXPECT_EQ(back[1].stamp_s, 0.75);
  back = parseEncoders("stamp_s,ticks_left,ticks_right\r\n\r\n1,2,3\r\n", "e.csv");
  ASSERT_EQ(back.size(), 1u);
  EXPECT_EQ(back[0].ticks_left, 2);
  EXPECT_TRUE(parseEncoders(std::string(kEncoderHeader), "e.csv").empty());
}

TEST(CsvLogs, EncoderErrorsNameFileLineAndField) {
  const std::string h = "stamp_s,ticks_left,ticks_right\n";
  auto parse = [](const std::string& t, const std::string& f) { return parseEncoders(t, f); };
  expectError(parse, "", "log.csv: empty file, expected the header");
  expectError(parse, "t,l,r\n1,2,3\n", "log.csv:1: expected the header");
  expectError(parse, h + "1,2,3\n2,3\n", "log.csv:3: expected 3 columns");
  expectError(parse, h + "1,2,3,4\n", "log.csv:2: expected 3 columns");
  expectError(parse, h + "1,2,x\n", "log.csv:2: ticks_right: not an integer");
  expectError(parse, h + "1,2.5,3\n", "log.csv:2: ticks_left: not an integer");
  expectError(parse, h + "nan,2,3\n", "log.csv:2: stamp_s: must be finite");
  expectError(parse, h + "1,2,3\n1,2,3\n", "log.csv:3: stamp_s: duplicate timestamp");
  expectError(parse, h + "1,2,3\n0.5,2,3\n", "log.csv:3: stamp_s: timestamp 0.5 after 1");
}

TEST(CsvLogs, ImuRoundTripsAndRejectsNonFinite) {
  const ImuLog log = {{1.0, 0.25, -9.5, -0.0}};
  const ImuLog back = parseImu(formatImu(log, "i.csv"), "i.csv");
  ASSERT_EQ(back.size(), 1u);
  EXPECT_EQ(back[0].gyro_z_radps, 0.25);
  EXPECT_TRUE(std::signbit(back[0].accel_y_mps2));
  const std::string h = std::string(kImuHeader) + "\n";
  auto parse = [](const std::string& t, const std::string& f) { return parseImu(t, f); };
  expectError(parse, h + "1,0,inf,0\n", "log.csv:2: accel_x_mps2: must be finite");
  expectError(parse, h + "1,0,0,\n", "log.csv:2: accel_y_mps2: empty");
  expectError(parse, h + "1,0,0\n", "log.csv:2: expected 4 columns");
  EXPECT_THROW(formatImu({{1.0, std::nan(""), 0, 0}}, "i.csv"), InputError);
  EXPECT_THROW(formatImu({{1.0, 0, 0, 0}, {1.0, 0, 0, 0}}, "i.csv"), InputError);
}

}  // namespace
}  // namespace slamprep::eval
