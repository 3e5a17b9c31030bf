#include "slamprep/eval/formats/dataset_io.hpp"

#include <fcntl.h>
#include <stdio.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>
#include <system_error>
#include <vector>

#include "slamprep/core/atomic_file.hpp"
#include "slamprep/core/dataset.hpp"
#include "slamprep/core/error.hpp"
#include "slamprep/core/input_file.hpp"
#include "slamprep/core/partial_cleanup.hpp"
#include "slamprep/eval/formats/csv_logs.hpp"
#include "slamprep/eval/formats/dataset_json.hpp"
#include "slamprep/eval/formats/scan_jsonl.hpp"
#include "slamprep/eval/formats/text_io.hpp"
#include "slamprep/eval/formats/tum.hpp"

namespace slamprep::eval {
namespace {

namespace fs = std::filesystem;

// "out/run1/" and "out/run1" name the same directory.
fs::path withoutTrailingSlash(const fs::path& dir) {
  fs::path p = dir.lexically_normal();
  return p.has_filename() ? p : p.parent_path();
}

[[noreturn]] void systemError(const fs::path& where, const std::string& what) {
  throw InputError(where.string(), what + ": " + std::strerror(errno));
}

void syncDirectory(const fs::path& dir) {
  const int fd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;  // best effort: some filesystems refuse to open directories
  ::fsync(fd);
  ::close(fd);
}

// Moves the complete `partial` onto `dir`; the old dataset (if any) is deleted afterwards. An
// output given without --force (refuseToReplace) is only ever created, never replaced.
void publish(const fs::path& partial, const fs::path& dir,
             const ReplaceableDirectory& replaceable) {
  std::error_code ec;
  if (!mayReplace(dir) || !fs::exists(fs::symlink_status(dir, ec))) {
    renameIntoPlace(partial, dir);
    return;
  }
  std::error_code dir_ec;
  if (!fs::is_directory(dir, dir_ec) || !replaceable(dir))
    throw InputError(dir.string(),
                     "exists and is not a dataset directory (no dataset.json); refusing to "
                     "replace it");
  if (::renameat2(AT_FDCWD, partial.c_str(), AT_FDCWD, dir.c_str(), RENAME_EXCHANGE) == 0) {
    fs::remove_all(partial, ec);  // now holds the old dataset
    return;
  }
  // No RENAME_EXCHANGE on this filesystem: move the old one aside, then the new one in. `dir` is
  // briefly absent, never half written.
  const fs::path old = partialSibling(dir, "old");
  fs::remove_all(old, ec);
  if (::rename(dir.c_str(), old.c_str()) != 0) systemError(dir, "cannot move the old dataset");
  if (::rename(partial.c_str(), dir.c_str()) != 0) {
    const int saved = errno;
    ::rename(old.c_str(), dir.c_str());
    errno = saved;
    systemError(dir, "cannot rename into place");
  }
  fs::remove_all(old, ec);
}

}  // namespace

bool isReplaceableDataset(const fs::path& dir) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return false;
  return fs::is_empty(dir, ec) || fs::exists(dir / kDatasetJson, ec);
}

fs::path partialDirectory(const fs::path& dir) {
  return partialSibling(withoutTrailingSlash(dir));
}

void publishDirectoryAtomically(const fs::path& dir,
                                const std::function<void(const fs::path&)>& fill,
                                const ReplaceableDirectory& replaceable) {
  const fs::path target = withoutTrailingSlash(dir);
  const fs::path partial = partialDirectory(target);
  std::error_code ec;
  if (target.has_parent_path()) {
    fs::create_directories(target.parent_path(), ec);
    if (ec) throw InputError(target.parent_path().string(), "cannot create: " + ec.message());
  }
  const PartialInFlight in_flight(partial);  // removed if a signal ends the process
  fs::remove_all(partial, ec);               // a stale one from a crashed process with our pid
  if (!fs::create_directory(partial, ec))
    throw InputError(partial.string(), "cannot create: " + ec.message());
  try {
    fill(partial);
    syncDirectory(partial);
    publish(partial, target, replaceable);
    syncDirectory(target.parent_path());
  } catch (...) {
    fs::remove_all(partial, ec);
    throw;
  }
}

namespace {

/// One odometry source of a dataset and the time span it covers.
struct OdometrySpan {
  const char* file;
  double first_s;
  double last_s;
};

/// The odometry sources the dataset has (encoders.csv, odom_nominal.tum): de-skew and calibration
/// read whichever they are given, so every present one must cover every beam.
std::vector<OdometrySpan> odometrySpans(const Dataset& d) {
  std::vector<OdometrySpan> spans;
  if (!d.encoders.empty())
    spans.push_back({kEncodersCsv, d.encoders.front().stamp_s, d.encoders.back().stamp_s});
  if (!d.odom_nominal.empty())
    spans.push_back({kOdomNominalTum, d.odom_nominal.frontStamp(), d.odom_nominal.backStamp()});
  return spans;
}

std::string seconds(double t) {
  std::string out;
  appendDouble(out, t);
  return out;
}

void checkScansCovered(const Dataset& d, const std::vector<std::size_t>& scan_lines,
                       const std::string& scans_file) {
  const std::vector<OdometrySpan> spans = odometrySpans(d);
  // No odometry at all: the scans can still be matched (ICP); odometry methods refuse later.
  for (std::size_t k = 0; k < d.scans.size(); ++k) {
    const LaserScan& scan = d.scans[k].scan;
    for (const OdometrySpan& span : spans) {
      if (scan.stamp_s >= span.first_s && scan.endTime() <= span.last_s) continue;
      throw InputError(TextLocation{scans_file, scan_lines[k]}.str(),
                       "stamp_s: the scan's beams (" + seconds(scan.stamp_s) + " .. " +
                           seconds(scan.endTime()) + " s) are not covered by the odometry in " +
                           span.file + " (" + seconds(span.first_s) + " .. " +
                           seconds(span.last_s) + " s)");
    }
  }
}

// What readDataset would refuse is not written: scan k goes to line k + 1 of scans.jsonl.
void checkWritable(const Dataset& dataset, const std::filesystem::path& named_as) {
  std::vector<std::size_t> scan_lines(dataset.scans.size());
  for (std::size_t k = 0; k < scan_lines.size(); ++k) scan_lines[k] = k + 1;
  checkScansCovered(dataset, scan_lines, (named_as / kScansJsonl).string());
}

}  // namespace

namespace {

// Every file but scans.jsonl; errors name the final path: that is the file the user asked for.
void writeStreamFiles(const std::filesystem::path& dir, const Dataset& dataset,
                      const std::filesystem::path& named_as) {
  auto name = [&](const char* file) { return (named_as / file).string(); };
  writeTextFile(dir / kDatasetJson, formatDatasetInfo(dataset.info, name(kDatasetJson)));
  writeTum(dir / kGroundTruthTum, dataset.groundtruth, name(kGroundTruthTum));
  writeTum(dir / kOdomNominalTum, dataset.odom_nominal, name(kOdomNominalTum));
  if (!dataset.odometry_logged.empty())
    writeTum(dir / kOdometryLoggedTum, dataset.odometry_logged, name(kOdometryLoggedTum));
  writeEncoders(dir / kEncodersCsv, dataset.encoders, name(kEncodersCsv));
  writeImu(dir / kImuCsv, dataset.imu, name(kImuCsv));
}

}  // namespace

void writeDatasetFiles(const std::filesystem::path& dir, const Dataset& dataset,
                       const std::filesystem::path& named_as) {
  checkWritable(dataset, named_as);
  writeStreamFiles(dir, dataset, named_as);
  writeScans(dir / kScansJsonl, dataset.scans, (named_as / kScansJsonl).string());
}

void writeDatasetFiles(const std::filesystem::path& dir, const Dataset& dataset,
                       const std::filesystem::path& named_as,
                       const std::function<bool(ScanRecord&)>& scans) {
  writeStreamFiles(dir, dataset, named_as);
  writeScans(dir / kScansJsonl, scans, (named_as / kScansJsonl).string());
}

void writeDataset(const std::filesystem::path& dir, const Dataset& dataset) {
  checkWritable(dataset, dir);  // before the partial directory exists
  publishDirectoryAtomically(
      dir, [&](const std::filesystem::path& partial) { writeDatasetFiles(partial, dataset, dir); });
}

Dataset readDataset(const std::filesystem::path& dir) {
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec))
    throw InputError(dir.string(), "not a dataset directory (missing or not a directory)");
  auto text = [&](const char* file) { return readTextFile(dir / file); };
  auto name = [&](const char* file) { return (dir / file).string(); };
  Dataset d;
  d.info = parseDatasetInfo(readInputFile(dir / kDatasetJson, kDatasetJson, kMaxConfigFileBytes),
                            name(kDatasetJson));
  d.groundtruth = parseTum(text(kGroundTruthTum), name(kGroundTruthTum));
  d.odom_nominal = parseTum(text(kOdomNominalTum), name(kOdomNominalTum));
  if (std::filesystem::exists(dir / kOdometryLoggedTum, ec))
    d.odometry_logged = parseTum(text(kOdometryLoggedTum), name(kOdometryLoggedTum));
  d.encoders = parseEncoders(text(kEncodersCsv), name(kEncodersCsv));
  d.imu = parseImu(text(kImuCsv), name(kImuCsv));
  std::vector<std::size_t> scan_lines;
  d.scans = parseScans(text(kScansJsonl), name(kScansJsonl), &scan_lines);
  checkScansCovered(d, scan_lines, name(kScansJsonl));
  return d;
}

}  // namespace slamprep::eval
