#pragma once
// encoders.csv and imu.csv (docs/dataset.md): a fixed header line, then one sample per line.

#include <filesystem>
#include <string>
#include <string_view>

#include "slamprep/core/samples.hpp"

namespace slamprep::eval {

inline constexpr std::string_view kEncoderHeader = "stamp_s,ticks_left,ticks_right";
inline constexpr std::string_view kImuHeader = "stamp_s,gyro_z_radps,accel_x_mps2,accel_y_mps2";

/// Throws InputError("file:line") for non-finite or non-increasing stamps (what the reader
/// rejects).
std::string formatEncoders(const EncoderLog& encoders, const std::string& file);
/// The same text written to `path` piece by piece.
void writeEncoders(const std::filesystem::path& path, const EncoderLog& encoders,
                   const std::string& file);
/// Rejects a wrong header, wrong column counts, non-numbers, NaN/Inf and unsorted/duplicate stamps.
EncoderLog parseEncoders(std::string_view text, const std::string& file);

/// Throws InputError("file:line") for non-finite values or non-increasing stamps.
std::string formatImu(const ImuLog& imu, const std::string& file);
/// The same text written to `path` piece by piece.
void writeImu(const std::filesystem::path& path, const ImuLog& imu, const std::string& file);
ImuLog parseImu(std::string_view text, const std::string& file);

}  // namespace slamprep::eval
