// `slamprep export`: a dataset as a ROS 2 bag (MCAP), CARMEN log, TUM/KITTI trajectories or CSM
// laser_data JSON (docs/export.md).
#include <iostream>

#include "app/commands.hpp"
#include "eval/formats/export.hpp"

namespace slamprep::app {
namespace {

struct ExportFlags {
  std::string dataset;
  std::string compression = "zstd";
  std::string format;
  std::string out;
  eval::ExportParams params;
};

int runExport(ExportFlags flags) {
  const eval::ExportFormat format = eval::parseExportFormat(flags.format);
  flags.params.mcap_compression = eval::parseCompression(flags.compression);
  const eval::ExportInput input = eval::loadExportInput(flags.dataset, flags.params);
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
  cli->add_option("--calibration", flags->params.calibration_file,
                  "calibrate --json output for the calibrated odometry (default: "
                  "DATASET/calibration.json if present)");
  cli->add_option("--scans", flags->params.scans,
                  "carmen/csm: 'scans' or a de-skew method (reads deskewed_<method>.jsonl)")
      ->capture_default_str();
  cli->add_option("--chunk-size", flags->params.mcap_chunk_size_bytes,
                  "mcap: bytes per chunk; 0 writes an unchunked file")
      ->capture_default_str();
  cli->add_option("--compression", flags->compression, "mcap: chunk compression")
      ->check(CLI::IsMember({"none", "zstd", "lz4"}))
      ->capture_default_str();
  cli->add_option("--ground-truth-frame", flags->params.world_frame,
                  "mcap: frame of /ground_truth (e.g. map or world)")
      ->capture_default_str();
  return {cli, [flags] { return runExport(*flags); }};
}

}  // namespace slamprep::app
