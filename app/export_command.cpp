// `slamprep export`: a dataset as a ROS 2 bag (MCAP), CARMEN log, TUM/KITTI trajectories or CSM
// laser_data JSON (docs/export.md).
#include <filesystem>
#include <iostream>

#include "algo/calibration/calibration_json.hpp"
#include "app/commands.hpp"
#include "eval/formats/export.hpp"

namespace slamprep::app {
namespace {

namespace fs = std::filesystem;

struct ExportFlags {
  std::string dataset;
  std::string format;
  std::string out;
  std::string calibration;  // default DATASET/calibration.json, when present
  eval::ExportParams params;
};

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
        best->result.geometry, std::string(algo::calibrationMethodName(best->method))};
  else
    input.notes.push_back(file.string() +
                          " holds no ok calibration: calibrated odometry not written");
}

int runExport(const ExportFlags& flags) {
  const eval::ExportFormat format = eval::parseExportFormat(flags.format);
  eval::ExportInput input = eval::loadExportInput(flags.dataset);
  addCalibration(flags, input);
  const eval::ExportResult result = eval::exportDataset(input, format, flags.out, flags.params);
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
      "export",
      "Write a dataset as an MCAP ROS 2 bag, a CARMEN log, TUM or KITTI trajectories, "
      "or CSM laser_data JSON.");
  cli->add_option("DATASET", flags->dataset, "dataset directory")->required();
  cli->add_option("--format", flags->format, "mcap|carmen|tum|kitti|csm")
      ->required()
      ->check(CLI::IsMember({"mcap", "carmen", "tum", "kitti", "csm"}));
  cli->add_option("--out", flags->out, "output file (mcap, carmen, csm) or directory (tum, kitti)")
      ->required();
  cli->add_option("--calibration", flags->calibration,
                  "calibrate --json output for the calibrated odometry (default: "
                  "DATASET/calibration.json if present)");
  cli->add_option("--scans", flags->params.scans,
                  "carmen/csm: 'scans' or a de-skew method (reads deskewed_<method>.jsonl)")
      ->capture_default_str();
  cli->add_option("--chunk-size", flags->params.mcap_chunk_size_bytes,
                  "mcap: bytes per chunk; 0 writes an unchunked file")
      ->capture_default_str();
  return {cli, [flags] { return runExport(*flags); }};
}

}  // namespace slamprep::app
