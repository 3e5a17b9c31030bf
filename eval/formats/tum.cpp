#include "slamprep/eval/formats/tum.hpp"

#include <cmath>
#include <vector>

#include "slamprep/core/error.hpp"
#include "slamprep/eval/formats/text_io.hpp"

namespace slamprep::eval {
namespace {

// Steps one coordinate of (qz, qw) ulp by ulp until 2 * atan2(qz, qw) hits the target yaw.
// Each ulp of qz (or qw) moves the angle by less than one ulp of the half angle (sin h <= h,
// cos h <= 1), so the walk cannot jump over the target.
bool walkToExact(double half_yaw, double& qz, double& qw, bool move_qz) {
  constexpr int kMaxSteps = 64;
  for (int step = 0; step < kMaxSteps; ++step) {
    const double angle = std::atan2(qz, qw);
    if (angle == half_yaw) return true;
    const bool increase_angle = angle < half_yaw;
    if (move_qz)
      qz = std::nextafter(qz, increase_angle ? HUGE_VAL : -HUGE_VAL);
    else
      qw = std::nextafter(qw, increase_angle ? -HUGE_VAL : HUGE_VAL);
  }
  return false;
}

const std::array<const char*, 8> kTumColumns = {"t", "x", "y", "z", "qx", "qy", "qz", "qw"};

}  // namespace

YawQuaternion yawToQuaternion(double yaw_rad) {
  const double half = yaw_rad / 2;
  YawQuaternion q{std::sin(half), std::cos(half)};
  if (walkToExact(half, q.qz, q.qw, true)) return q;
  q = {std::sin(half), std::cos(half)};
  if (walkToExact(half, q.qz, q.qw, false)) return q;
  return {std::sin(half), std::cos(half)};  // unreachable for normal doubles (tests cover it)
}

double yawFromQuaternion(double qx, double qy, double qz, double qw) {
  if (qx == 0.0 && qy == 0.0) return normalizeAngle(2.0 * std::atan2(qz, qw));
  // Heading of R(q) e_x: atan2(R10, R00) with the unnormalised rotation matrix.
  return std::atan2(2.0 * (qw * qz + qx * qy), qw * qw + qx * qx - qy * qy - qz * qz);
}

namespace {

constexpr const char* kTumHeader = "# t x y z qx qy qz qw\n";

void appendTumRow(std::string& out, const PoseSeries& poses, std::size_t k,
                  const std::string& file) {
  const auto& sample = poses[k];
  const SE2& T = sample.value;
  const TextLocation where{file, k + 2};  // after the header line
  if (!std::isfinite(sample.stamp_s) || !std::isfinite(T.x) || !std::isfinite(T.y) ||
      !std::isfinite(T.yaw))
    throw InputError(where.str(), "t x y yaw: must be finite to be written");
  if (k > 0) requireIncreasing(poses[k - 1].stamp_s, sample.stamp_s, where, "t");
  const YawQuaternion q = yawToQuaternion(T.yaw);
  appendDouble(out, sample.stamp_s);
  out += ' ';
  appendDouble(out, T.x);
  out += ' ';
  appendDouble(out, T.y);
  out += " 0 0 0 ";
  appendDouble(out, q.qz);
  out += ' ';
  appendDouble(out, q.qw);
  out += '\n';
}

}  // namespace

std::string formatTum(const PoseSeries& poses, const std::string& file) {
  std::string out = kTumHeader;
  out.reserve(out.size() + poses.size() * 96);
  for (std::size_t k = 0; k < poses.size(); ++k) appendTumRow(out, poses, k, file);
  return out;
}

void writeTum(const std::filesystem::path& path, const PoseSeries& poses, const std::string& file) {
  writeRows(path, kTumHeader, poses.size(),
            [&](std::string& out, std::size_t k) { appendTumRow(out, poses, k, file); });
}

PoseSeries parseTum(std::string_view text, const std::string& file) {
  PoseSeries poses;
  forEachNumberRow(
      text, file, kTumColumns, [&](const auto& values, const TextLocation& where, auto&) {
        const double norm = std::sqrt(values[4] * values[4] + values[5] * values[5] +
                                      values[6] * values[6] + values[7] * values[7]);
        if (std::abs(norm - 1.0) > 1e-3)
          throw InputError(where.str(), "qx qy qz qw: quaternion norm " + std::to_string(norm) +
                                            " is not 1 (column order must be t x y z qx qy qz qw)");
        if (!poses.empty()) requireIncreasing(poses.backStamp(), values[0], where, "t");
        poses.push_back(values[0],
                        SE2(values[1], values[2],
                            yawFromQuaternion(values[4], values[5], values[6], values[7])));
      });
  return poses;
}

PoseSeries readTum(const std::filesystem::path& path) {
  return parseTum(readTextFile(path), path.string());
}

}  // namespace slamprep::eval
