#pragma once
// The dataset directory on disk (docs/dataset.md): reading, writing, file names and the atomic
// directory publish.

#include <filesystem>
#include <functional>

#include "slamprep/core/dataset.hpp"

namespace slamprep::eval {

/// Writes `dataset` to `dir` atomically: into a temporary sibling first, renamed when complete.
void writeDataset(const std::filesystem::path& dir, const Dataset& dataset);

/// Writes the dataset's files into the existing directory `dir` (e.g. the partial directory of
/// publishDirectoryAtomically, with more files beside them); messages name `named_as`.
void writeDatasetFiles(const std::filesystem::path& dir, const Dataset& dataset,
                       const std::filesystem::path& named_as);
/// The same with scans.jsonl written from `scans` (dataset.scans is not written; the source
/// checks that the odometry covers each scan, e.g. a spilled import's ScanStream).
void writeDatasetFiles(const std::filesystem::path& dir, const Dataset& dataset,
                       const std::filesystem::path& named_as,
                       const std::function<bool(ScanRecord&)>& scans);

/// Reads a dataset directory. Throws InputError naming file, line and field on malformed input.
Dataset readDataset(const std::filesystem::path& dir);

inline constexpr const char* kDatasetJson = "dataset.json";
inline constexpr const char* kGroundTruthTum = "groundtruth.tum";
inline constexpr const char* kOdomNominalTum = "odom_nominal.tum";
/// Optional: written only when Dataset::odometry_logged is not empty, read when present.
inline constexpr const char* kOdometryLoggedTum = "odometry_logged.tum";
inline constexpr const char* kEncodersCsv = "encoders.csv";
inline constexpr const char* kImuCsv = "imu.csv";
inline constexpr const char* kScansJsonl = "scans.jsonl";

/// `<dir>.partial-<pid>` (core/atomic_file.hpp, partialSibling): the sibling a directory is
/// written into before it is published.
std::filesystem::path partialDirectory(const std::filesystem::path& dir);

/// Whether an existing directory may be replaced by a new one.
using ReplaceableDirectory = std::function<bool(const std::filesystem::path&)>;

/// The default rule: an empty directory or one that holds a dataset.json.
bool isReplaceableDataset(const std::filesystem::path& dir);

/// Creates the partial sibling of `dir`, lets `fill(partial_dir)` write into it, then renames it
/// onto `dir`. An existing `dir` is replaced only when `replaceable(dir)` and not marked by
/// refuseToReplace (core/atomic_file.hpp: an output given without --force, which must not appear
/// while the command runs); it is swapped atomically with renameat2(RENAME_EXCHANGE) where the
/// filesystem supports it. On any exception, and on SIGINT/SIGTERM/SIGHUP once
/// removePartialsOnSignal() is installed, the partial directory is removed; `dir` is untouched.
void publishDirectoryAtomically(const std::filesystem::path& dir,
                                const std::function<void(const std::filesystem::path&)>& fill,
                                const ReplaceableDirectory& replaceable = isReplaceableDataset);

}  // namespace slamprep::eval
