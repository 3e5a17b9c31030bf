#include "slamprep/eval/formats/csv_logs.hpp"

#include <cmath>
#include <initializer_list>
#include <vector>

#include "slamprep/core/error.hpp"
#include "slamprep/eval/formats/text_io.hpp"

namespace slamprep::eval {
namespace {

// Calls row(fields, where) for every data line after checking the header; blank lines skip.
template <std::size_t N, typename Row>
void forEachCsvRow(std::string_view text, const std::string& file, std::string_view header,
                   Row&& row) {
  LineCursor cursor(text);
  std::string_view line;
  std::vector<std::string_view> fields;
  bool seen_header = false;
  while (cursor.next(line)) {
    line = trim(line);
    if (line.empty()) continue;
    const TextLocation where{file, cursor.lineNumber()};
    if (!seen_header) {
      if (line != header)
        throw InputError(where.str(), "expected the header \"" + std::string(header) + "\"");
      seen_header = true;
      continue;
    }
    splitFields(line, ',', fields);
    if (fields.size() != N)
      throw InputError(where.str(), "expected " + std::to_string(N) + " columns (" +
                                        std::string(header) + "), got " +
                                        std::to_string(fields.size()));
    row(fields, where);
  }
  if (!seen_header)
    throw InputError(file, "empty file, expected the header \"" + std::string(header) + "\"");
}

// The writer's side of the reader's checks; data lines start at line 2, after the header.
void checkWritable(const std::string& file, std::size_t index, double stamp_s,
                   const double* previous_stamp_s, std::initializer_list<double> values) {
  const TextLocation where{file, index + 2};
  if (!std::isfinite(stamp_s)) throw InputError(where.str(), "stamp_s: must be finite");
  for (double v : values)
    if (!std::isfinite(v)) throw InputError(where.str(), "values must be finite to be written");
  if (previous_stamp_s) requireIncreasing(*previous_stamp_s, stamp_s, where, "stamp_s");
}

void appendEncoderRow(std::string& out, const EncoderLog& encoders, std::size_t k,
                      const std::string& file) {
  const EncoderSample& e = encoders[k];
  checkWritable(file, k, e.stamp_s, k ? &encoders[k - 1].stamp_s : nullptr, {});
  appendDouble(out, e.stamp_s);
  out += ',';
  appendInt(out, e.ticks_left);
  out += ',';
  appendInt(out, e.ticks_right);
  out += '\n';
}

void appendImuRow(std::string& out, const ImuLog& imu, std::size_t k, const std::string& file) {
  const ImuSample& s = imu[k];
  checkWritable(file, k, s.stamp_s, k ? &imu[k - 1].stamp_s : nullptr,
                {s.gyro_z_radps, s.accel_x_mps2, s.accel_y_mps2});
  appendDouble(out, s.stamp_s);
  out += ',';
  appendDouble(out, s.gyro_z_radps);
  out += ',';
  appendDouble(out, s.accel_x_mps2);
  out += ',';
  appendDouble(out, s.accel_y_mps2);
  out += '\n';
}

}  // namespace

std::string formatEncoders(const EncoderLog& encoders, const std::string& file) {
  std::string out(kEncoderHeader);
  out += '\n';
  out.reserve(out.size() + encoders.size() * 48);
  for (std::size_t k = 0; k < encoders.size(); ++k) appendEncoderRow(out, encoders, k, file);
  return out;
}

void writeEncoders(const std::filesystem::path& path, const EncoderLog& encoders,
                   const std::string& file) {
  writeRows(path, std::string(kEncoderHeader) + '\n', encoders.size(),
            [&](std::string& out, std::size_t k) { appendEncoderRow(out, encoders, k, file); });
}

EncoderLog parseEncoders(std::string_view text, const std::string& file) {
  EncoderLog encoders;
  forEachCsvRow<3>(text, file, kEncoderHeader, [&](const auto& f, const TextLocation& where) {
    EncoderSample e;
    e.stamp_s = parseFiniteDouble(f[0], where, "stamp_s");
    if (!encoders.empty()) requireIncreasing(encoders.back().stamp_s, e.stamp_s, where, "stamp_s");
    e.ticks_left = parseInt64(f[1], where, "ticks_left");
    e.ticks_right = parseInt64(f[2], where, "ticks_right");
    encoders.push_back(e);
  });
  return encoders;
}

std::string formatImu(const ImuLog& imu, const std::string& file) {
  std::string out(kImuHeader);
  out += '\n';
  out.reserve(out.size() + imu.size() * 80);
  for (std::size_t k = 0; k < imu.size(); ++k) appendImuRow(out, imu, k, file);
  return out;
}

void writeImu(const std::filesystem::path& path, const ImuLog& imu, const std::string& file) {
  writeRows(path, std::string(kImuHeader) + '\n', imu.size(),
            [&](std::string& out, std::size_t k) { appendImuRow(out, imu, k, file); });
}

ImuLog parseImu(std::string_view text, const std::string& file) {
  ImuLog imu;
  forEachCsvRow<4>(text, file, kImuHeader, [&](const auto& f, const TextLocation& where) {
    ImuSample s;
    s.stamp_s = parseFiniteDouble(f[0], where, "stamp_s");
    if (!imu.empty()) requireIncreasing(imu.back().stamp_s, s.stamp_s, where, "stamp_s");
    s.gyro_z_radps = parseFiniteDouble(f[1], where, "gyro_z_radps");
    s.accel_x_mps2 = parseFiniteDouble(f[2], where, "accel_x_mps2");
    s.accel_y_mps2 = parseFiniteDouble(f[3], where, "accel_y_mps2");
    imu.push_back(s);
  });
  return imu;
}

}  // namespace slamprep::eval
