// `slamprep export`: a dataset as a ROS 2 bag (MCAP), CARMEN log, TUM/KITTI trajectories or CSM
// laser_data JSON (docs/export.md).
#include <filesystem>
#include <iostream>
#include <set>

#include "slamprep/algo/calibration/calibration_json.hpp"
#include "slamprep/algo/deskew/deskew.hpp"
#include "slamprep/app/choices.hpp"
#include "slamprep/app/commands.hpp"
#include "slamprep/app/common_flags.hpp"
#include "slamprep/app/outputs.hpp"
#include "slamprep/eval/formats/dataset_io.hpp"
#include "slamprep/eval/formats/export.hpp"

namespace slamprep::app {
namespace {

namespace fs = std::filesystem;

struct ExportFlags : CommonFlags {
  std::string dataset;
  std::string compression = "zstd";
  std::string format;
  std::string out;
  std::string calibration;  // default DATASET/calibration.json, when present
  eval::ExportParams params;
};

bool isDirectoryFormat(eval::ExportFormat format) {
  return format == eval::ExportFormat::kTum || format == eval::ExportFormat::kKitti;
}

// The files an export into a folder writes (eval::exportDataset): --force replaces a folder that
// holds nothing else (or nothing), never one with a file of the user's beside them.
bool isTrajectoryFolder(const fs::path& dir) {
  static const std::set<std::string> written = {
      "groundtruth.tum", "odom_nominal.tum", "odom_calibrated.tum",
      "groundtruth.txt", "odom_nominal.txt", "odom_calibrated.txt",
      "times.txt"};
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec))
    if (!entry.is_regular_file(ec) || !written.contains(entry.path().filename().string()))
      return false;
  return !ec;
}

void checkPaths(const ExportFlags& flags, eval::ExportFormat format) {
  checkInputDataset(flags.dataset, "DATASET");
  if (!flags.calibration.empty()) checkInputFile(flags.calibration, "--calibration");
  OutputGuard guard(flags.force);
  guard.input(flags.dataset, "DATASET").input(flags.calibration, "--calibration");
  if (isDirectoryFormat(format))
    guard.directory(flags.out, "--out", isTrajectoryFolder,
                    "a trajectories folder an export wrote (only groundtruth, odom_nominal, "
                    "odom_calibrated .tum/.txt and times.txt)");
  else
    guard.file(flags.out, "--out");
  guard.check();
}

// tum and kitti write several files: into a partial folder, published whole.
eval::ExportResult exportToFolder(const eval::ExportInput& input, eval::ExportFormat format,
                                  const ExportFlags& flags) {
  eval::ExportResult result;
  eval::publishDirectoryAtomically(
      flags.out,
      [&](const fs::path& partial) {
        result = eval::exportDataset(input, format, partial, flags.params);
      },
      isTrajectoryFolder);
  for (fs::path& file : result.files) file = fs::path(flags.out) / file.filename();
  return result;
}

// The best method of the calibration JSON (docs/calibration.md). A file given with --calibration
// must hold an ok entry; the implicit DATASET/calibration.json only earns a note.
void addCalibration(const ExportFlags& flags, eval::ExportInput& input) {
  const bool given = !flags.calibration.empty();
  const fs::path file =
      given ? fs::path(flags.calibration) : fs::path(flags.dataset) / "calibration.json";
  if (!given && !fs::exists(file)) return;
  const algo::CalibrationFile calibration = algo::readCalibrationJson(file);
  if (given) calibration.requireBest();  // an error when no entry is ok
  if (const algo::CalibrationRun* best = calibration.best())
    input.calibration = eval::CalibrationChoice{
        best->result.geometry, std::string(algo::calibrationMethodName(best->method)),
        best->relative_to_odometry};
  else
    input.notes.push_back(file.string() +
                          " holds no ok calibration: calibrated odometry not written");
}

int runExport(ExportFlags flags) {
  const eval::ExportFormat format = eval::parseExportFormat(flags.format);
  flags.params.mcap_compression = eval::parseCompression(flags.compression);
  checkPaths(flags, format);
  eval::ExportInput input = eval::loadExportInput(flags.dataset);
  addCalibration(flags, input);
  const eval::ExportResult result =
      isDirectoryFormat(format) ? exportToFolder(input, format, flags)
                                : eval::exportDataset(input, format, flags.out, flags.params);
  if (input.calibration)
    std::cout << "calibrated odometry: method " << input.calibration->method << "\n";
  for (const auto& [what, n] : result.counts) std::cout << "  " << what << ": " << n << "\n";
  for (const auto& file : result.files) std::cout << "wrote " << file.string() << "\n";
  for (const auto& note : result.notes) std::cerr << "export: note: " << note << "\n";
  return 0;
}

}  // namespace

Command addExportCommand(CLI::App& app) {
  auto flags = std::make_shared<ExportFlags>();
  auto* cli = app.add_subcommand(
      "export", "Write a dataset as MCAP, CARMEN, TUM or KITTI trajectories, or CSM JSON.");
  cli->add_option("DATASET", flags->dataset, "dataset directory")->required();
  cli->add_option("--format", flags->format, joinedNames(eval::kExportFormatNames, "|"))
      ->required()
      ->check(oneOf("format", namesOf(eval::kExportFormatNames)));
  cli->add_option("--out", flags->out,
                  "output file (mcap, carmen, csm) or directory (tum, kitti); an existing one "
                  "is refused unless --force")
      ->required()
      ->check(outputPath());
  addForce(cli, *flags, "an existing --out");
  cli->add_option("--calibration", flags->calibration,
                  "calibrate --json output for the calibrated odometry (default: "
                  "DATASET/calibration.json if present)");
  std::vector<std::string> scans = {"scans"};
  for (const std::string& m : namesOf(algo::kDeskewMethodNames)) scans.push_back(m);
  cli->add_option("--scans", flags->params.scans,
                  "carmen/csm: 'scans' or a de-skew method (reads deskewed_<method>.jsonl, "
                  "which `slamprep deskew --out` writes)")
      ->check(oneOf("scans", scans))
      ->capture_default_str();
  cli->add_option("--chunk-size", flags->params.mcap_chunk_size_bytes,
                  "mcap: bytes per chunk; 0 writes an unchunked file")
      ->capture_default_str();
  cli->add_option("--compression", flags->compression, "mcap: chunk compression")
      ->check(oneOf("compression", namesOf(eval::kCompressionNames)))
      ->capture_default_str();
  cli->add_option("--ground-truth-frame", flags->params.world_frame,
                  "mcap: frame of /ground_truth (e.g. map or world)")
      ->capture_default_str();
  return {cli, [flags] { return runExport(*flags); }};
}

}  // namespace slamprep::app
