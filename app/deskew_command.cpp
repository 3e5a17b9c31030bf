// `slamprep deskew`: lidar motion-distortion removal on a dataset, every method through one
// interface (algo/deskew), error against ground truth when the dataset has it (docs/deskew.md).
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>

#include "slamprep/algo/calibration/calibration_json.hpp"
#include "slamprep/algo/timing/dataset_stamps.hpp"
#include "slamprep/app/choices.hpp"
#include "slamprep/app/command_progress.hpp"
#include "slamprep/app/commands.hpp"
#include "slamprep/app/common_flags.hpp"
#include "slamprep/app/exit_codes.hpp"
#include "slamprep/app/outputs.hpp"
#include "slamprep/core/atomic_file.hpp"
#include "slamprep/core/dataset.hpp"
#include "slamprep/core/error.hpp"
#include "slamprep/core/odometry.hpp"
#include "slamprep/eval/formats/dataset_io.hpp"
#include "slamprep/eval/formats/scan_jsonl.hpp"
#include "slamprep/eval/pipeline/dataset_deskew.hpp"
#include "slamprep/eval/pipeline/deskew_json.hpp"
#include "slamprep/eval/pipeline/match_trajectory.hpp"

namespace slamprep::app {
namespace {

namespace fs = std::filesystem;

struct DeskewFlags : CommonFlags {
  std::string dataset;
  std::string method = "all";
  std::string reference = "first";
  std::string geometry;         // nominal (default) or true; a file here is the deprecated alias
  std::string calibration;      // calibrate --json output
  std::string out;              // nothing is written without it
  std::vector<double> window;   // --window T0 T1: scans whose stamp is inside count in the metrics
  std::string stamps = "auto";  // auto: jittered constant-rate streams back on their grids
  std::string sync = "none";    // auto: the wheels and gyro moved onto the scans' clock
  bool stamp_is_last_beam = false;
  bool no_write = false;  // deprecated: nothing is written without --out anyway
  int quadratic_pieces = 4;
};

/// The wheel geometry and lidar mount the odometry-based methods use.
struct Geometry {
  DiffDriveParams wheels;
  SE2 T_base_lidar;
  std::string source;  ///< what the user asked for, for the printout
};

/// The calibration JSON's best method (docs/calibration.md); its mount when it estimates one.
Geometry geometryFromCalibration(const std::string& file, const Dataset& dataset) {
  const algo::CalibrationRun best = algo::readCalibrationJson(file).requireBest();
  const SE2 T_base_lidar =
      best.result.estimates_mount ? best.result.T_base_lidar : dataset.info.T_base_lidar;
  return {best.result.geometry, T_base_lidar,
          file + " (method " + std::string(algo::calibrationMethodName(best.method)) + ")"};
}

Geometry chooseGeometry(const DeskewFlags& flags, const Dataset& dataset) {
  if (!flags.calibration.empty()) return geometryFromCalibration(flags.calibration, dataset);
  if (flags.geometry == "true") {
    if (!dataset.info.true_geometry)
      throw InputError("--geometry true", flags.dataset + " has no true geometry (a real log?)");
    return {*dataset.info.true_geometry, dataset.info.trueMount(), "true"};
  }
  return {dataset.info.nominal_geometry, dataset.info.T_base_lidar, "nominal"};
}

/// Why `method` cannot run on this dataset at all (algo::deskewMissingInput decides); nullopt
/// when its inputs are there.
std::optional<std::string> notApplicable(algo::DeskewMethod method, const Dataset& d,
                                         bool has_odometry) {
  const auto missing =
      algo::deskewMissingInput(method, {!d.groundtruth.empty(), has_odometry, !d.imu.empty()});
  if (!missing) return std::nullopt;
  // Where the dataset would have had it.
  static const std::map<algo::DeskewInput, std::string> kWhere = {
      {algo::DeskewInput::kGroundTruth, " (a real log?)"},
      {algo::DeskewInput::kOdometry, " (neither encoders nor odom_nominal)"},
      {algo::DeskewInput::kImu, " (imu.csv is empty)"}};
  return "no " + std::string(algo::deskewInputName(*missing)) + kWhere.at(*missing);
}

/// Flags and paths, before any data is read: --geometry's deprecated FILE form becomes
/// --calibration; outputs are refused unless --force, and never inside the input.
DeskewFlags checkFlags(DeskewFlags flags) {
  checkInputDataset(flags.dataset, "DATASET");
  if (!flags.geometry.empty() && flags.geometry != "nominal" && flags.geometry != "true") {
    if (!flags.calibration.empty())
      throw InputError("--geometry " + flags.geometry, "give --calibration FILE only");
    std::cerr << "deskew: note: --geometry FILE is deprecated; use --calibration FILE\n";
    flags.calibration = flags.geometry;
    flags.geometry.clear();
  }
  if (!flags.calibration.empty() && !flags.geometry.empty())
    throw InputError("--geometry " + flags.geometry,
                     "--calibration already gives the geometry; drop one of them");
  if (!flags.calibration.empty()) checkInputFile(flags.calibration, "--calibration");
  if (!flags.window.empty() && !(flags.window[0] <= flags.window[1]))
    throw InputError("--window", "T0 must not exceed T1");
  if (flags.no_write) {
    std::cerr << "deskew: note: --no-write is deprecated: nothing is written without --out\n";
    flags.out.clear();
  }
  OutputGuard guard(flags.force);
  guard.input(flags.dataset, "DATASET").input(flags.calibration, "--calibration");
  if (!flags.out.empty()) guard.dataset(flags.out, "--out");
  if (!flags.json_out.empty()) guard.file(flags.json_out, "--json");
  guard.check();
  return flags;
}

struct MethodRun {
  algo::DeskewMethod method;
  eval::DatasetDeskew result;
  std::vector<ScanRecord> output;  ///< de-skewed scans; refused ones as measured
};

MethodRun runMethod(algo::DeskewMethod method, const Dataset& d, const PoseSeries& odometry,
                    const Geometry& geometry, const DeskewFlags& flags) {
  StageReporter stages(std::string(algo::deskewMethodName(method)), 1);
  stages.begin("deskew");
  eval::DatasetDeskewOptions options;
  options.on_scan = [&](std::size_t done, std::size_t total) {
    stages.update(static_cast<double>(done) / total);
  };
  options.geometry = geometry.wheels;
  options.odometry = odometry;
  options.T_base_lidar = geometry.T_base_lidar;
  options.reference =
      parseName(algo::kReferenceTimeNames, flags.reference, "reference", "--reference");
  options.stamp_is_last_beam = flags.stamp_is_last_beam;
  options.params.quadratic_pieces = flags.quadratic_pieces;
  if (!flags.window.empty()) {
    options.measure_from_s = flags.window[0];
    options.measure_to_s = flags.window[1];
  }
  MethodRun run{method, eval::deskewDataset(d, method, options), {}};
  for (std::size_t k = 0; k < d.scans.size(); ++k) {
    const algo::DeskewResult& r = run.result.scans[k];
    ScanRecord rec = d.scans[k];  // a refused scan is written as measured: time_increment > 0
    rec.p_ref_true.clear();       // marks it not de-skewed
    if (r.ok) {
      rec.scan = r.repacked;
      rec.p_ref = r.p_ref;  // the exact points, for the CSM export's per-ray theta
      rec.T_world_base_true = d.groundtruth.at(r.reference_s);
      rec.T_odom_base_nominal = d.odom_nominal.at(r.reference_s);
    }
    run.output.push_back(std::move(rec));
  }
  return run;
}

/// One method's object in --json (docs/deskew.md): its name, the figures (null without truth),
/// then the counts and the refusals.
nlohmann::ordered_json toJson(const MethodRun& run) {
  const std::string method(algo::deskewMethodName(run.method));
  const std::size_t scans = run.result.scans.size();
  nlohmann::ordered_json out = {{"method", method}};
  out.update(eval::deskewFiguresJson(run.result, eval::AbsentFigure::kNull));
  // Over every scan, a refused one as measured (as `match` keeps it): comparable across methods.
  const auto& fallback = run.result.fallback_error_m;
  out["fallback_mean_m"] = fallback ? nlohmann::ordered_json(fallback->mean) : nullptr;
  out["fallback_p95_m"] = fallback ? nlohmann::ordered_json(fallback->p95) : nullptr;
  out.update({{"seconds", run.result.seconds},
              {"scans", scans},
              {"refused", run.result.refused},
              {"ok", scans - run.result.refused},
              {"refused_by_reason", eval::refusedByReason(run.result.refusals)},
              {"warnings", run.result.warnings},
              {"refusals", eval::deskewRefusalsJson(run.result, method)}});
  return out;
}

/// "not-bracketed 3, sample-gap 1": refused scans counted by reason.
std::string reasonCounts(const std::map<std::string, int>& counts) {
  std::string out;
  for (const auto& [reason, n] : counts)
    out += (out.empty() ? "" : ", ") + reason + " " + std::to_string(n);
  return out;
}

void printRow(const MethodRun& run) {
  std::cout << std::left << std::setw(16) << algo::deskewMethodName(run.method) << std::right
            << std::fixed;
  if (const auto& e = run.result.error_m)
    std::cout << std::setprecision(3) << std::setw(10) << e->mean * 1e3 << std::setw(10)
              << e->rmse * 1e3 << std::setw(10) << e->p95 * 1e3 << std::setw(10) << e->max * 1e3
              << std::setw(10) << e->count;
  else
    std::cout << std::setw(50) << "(no ground truth)";
  if (const auto& r = run.result.repacked_error_m)
    std::cout << std::setprecision(3) << std::setw(12) << r->mean * 1e3 << std::setw(12)
              << r->p95 * 1e3 << std::setw(8) << run.result.repacked_lost_beams;
  else
    std::cout << std::setw(32) << "";
  std::cout << std::setprecision(4) << std::setw(10) << run.result.seconds << std::setw(9)
            << run.result.refused << "\n";
  const std::size_t scans = run.result.scans.size();
  // The error figures cover the scans de-skewed: say how many of all, and why the others not.
  if (run.result.refused > 0)
    std::cout << "    ok " << scans - run.result.refused << " of " << scans
              << " scans; refused: " << reasonCounts(eval::refusedByReason(run.result.refusals))
              << "\n";
  // The figure a method that refuses different scans can be compared by (`fallback_*`).
  if (run.result.refused > 0 && run.result.fallback_error_m)
    std::cout << "    all scans, the refused as measured: mean " << std::setprecision(3)
              << run.result.fallback_error_m->mean * 1e3 << " mm, p95 "
              << run.result.fallback_error_m->p95 * 1e3 << " mm\n";
  // A method that falls back (ICP failed: odometry alone, or the last motion) still counts as
  // de-skewed: say how often, or a mean equal to another method's is a puzzle.
  if (run.result.warnings > 1)
    std::cout << "    " << run.result.warnings
              << " warnings (fell back or kept the round before; the first below)\n";
  if (!run.result.first_note.empty())
    std::cout << "    first note: " << run.result.first_note << "\n";
}

/// The methods to run: the one asked for, or for `all` every one that applies to the data.
struct MethodChoice {
  std::vector<algo::DeskewMethod> run;
  std::vector<std::pair<algo::DeskewMethod, std::string>> not_applicable;
};

MethodChoice chooseMethods(const DeskewFlags& flags, const Dataset& d, bool has_odometry) {
  MethodChoice choice;
  const std::vector<algo::DeskewMethod> asked =
      flags.method == "all" ? algo::allDeskewMethods()
                            : std::vector<algo::DeskewMethod>{parseName(
                                  algo::kDeskewMethodNames, flags.method, "method", "--method")};
  for (const auto m : asked) {
    if (auto reason = notApplicable(m, d, has_odometry))
      choice.not_applicable.emplace_back(m, std::move(*reason));
    else
      choice.run.push_back(m);
  }
  return choice;
}

void printHeader(const DeskewFlags& flags, const Dataset& d, const Geometry& geometry) {
  std::cout << "de-skew of " << d.scans.size() << " scans, reference " << flags.reference
            << ", geometry " << geometry.source << "\n"
            << std::left << std::setw(16) << "method" << std::right << std::setw(10) << "mean mm"
            << std::setw(10) << "rms mm" << std::setw(10) << "p95 mm" << std::setw(10) << "max mm"
            << std::setw(10) << "beams" << std::setw(12) << "repacked mm" << std::setw(12)
            << "rp p95 mm" << std::setw(8) << "lost" << std::setw(10) << "seconds" << std::setw(9)
            << "refused"
            << "\n";
}

/// Odometry for the chosen geometry: the dataset's own for nominal, else re-integrated.
PoseSeries odometryForGeometry(const Dataset& d, const Geometry& geometry) {
  return geometry.source == "nominal" && !d.odom_nominal.empty()
             ? d.odom_nominal
             : integrateEncoders(d.encoders, geometry.wheels, d.info.ticks_per_revolution);
}

/// What the methods run so far add up to: their --json objects, refusals and written files.
struct DeskewTally {
  nlohmann::ordered_json json = nlohmann::ordered_json::array();
  std::size_t fully_refused = 0, with_refusals = 0;
  std::map<std::string, int> refused_by_reason;  // over every method run
  std::vector<std::string> written;

  void add(const MethodRun& run, std::size_t scan_count) {
    json.push_back(toJson(run));
    fully_refused += run.result.refused == static_cast<int>(scan_count);
    with_refusals += run.result.refused > 0;
    for (const auto& [reason, n] : eval::refusedByReason(run.result.refusals))
      refused_by_reason[reason] += n;
  }
};

/// Every method in turn, one table row each; with --out its scans go into the folder being
/// published (partial).
void runMethods(const DeskewFlags& flags, const MethodChoice& methods, const Dataset& d,
                const PoseSeries& odometry, const Geometry& geometry, const fs::path* partial,
                DeskewTally& tally) {
  CommandProgress progress(methods.run.size(), "methods", "deskew", !flags.quiet);
  for (const auto m : methods.run) {
    const MethodRun run = runMethod(m, d, odometry, geometry, flags);
    progress.advance(std::string(algo::deskewMethodName(m)));
    progress.clearLine();
    printRow(run);
    tally.add(run, d.scans.size());
    if (!partial) continue;
    const std::string name = "deskewed_" + std::string(algo::deskewMethodName(m)) + ".jsonl";
    writeFileAtomic(*partial / name,
                    eval::formatScans(run.output, (fs::path(flags.out) / name).string()));
    tally.written.push_back(name);
  }
}

void printFooter(const DeskewFlags& flags, const MethodChoice& methods, const DeskewTally& tally) {
  if (!tally.refused_by_reason.empty())
    std::cout << "refused scans by reason, all methods: " << reasonCounts(tally.refused_by_reason)
              << "\n";
  for (const auto& [m, reason] : methods.not_applicable)
    std::cout << std::left << std::setw(16) << algo::deskewMethodName(m)
              << "not applicable: " << reason << "\n";
  if (flags.out.empty())
    std::cout << "no --out: no de-skewed scans written\n";
  else
    std::cout << "wrote " << flags.out << ": a copy of the dataset plus "
              << joined(tally.written, ", ") << "\n";
}

/// An explicitly asked method that does not apply is a refusal; under `all` it is not asked.
int deskewExitCode(const DeskewFlags& flags, const MethodChoice& methods,
                   const DeskewTally& tally) {
  const std::size_t asked_refused =
      tally.fully_refused + (flags.method == "all" ? 0 : methods.not_applicable.size());
  const std::size_t asked =
      methods.run.size() + (flags.method == "all" ? 0 : methods.not_applicable.size());
  return refusalExitCode(asked_refused == asked, tally.with_refusals + asked_refused > 0,
                         flags.strict);
}

int runDeskew(const DeskewFlags& given) {
  const DeskewFlags flags = checkFlags(given);
  Dataset d = eval::readDataset(flags.dataset);
  if (d.scans.empty()) throw InputError(flags.dataset, "has no scans to de-skew");
  const std::string stamps =
      flags.stamps == "auto" ? algo::stampsSummary(algo::regularizeStamps(d)) : "";
  const double clock_sync_s =
      flags.sync == "auto" ? eval::syncOntoScans(d, "none", flags.stamp_is_last_beam) : 0.0;
  const Geometry geometry = chooseGeometry(flags, d);
  const PoseSeries odometry = odometryForGeometry(d, geometry);
  const MethodChoice methods = chooseMethods(flags, d, !odometry.empty());
  printHeader(flags, d, geometry);
  std::cout << stamps;
  if (clock_sync_s != 0.0)
    std::cout << "--sync auto: the scans lagged the wheels by " << clock_sync_s
              << " s; the wheels (and the gyro) moved onto the scans' clock\n";
  DeskewTally tally;
  if (flags.out.empty()) {
    runMethods(flags, methods, d, odometry, geometry, nullptr, tally);
  } else {
    eval::publishDirectoryAtomically(flags.out, [&](const fs::path& partial) {
      eval::writeDatasetFiles(partial, d, flags.out);
      runMethods(flags, methods, d, odometry, geometry, &partial, tally);
    });
  }
  printFooter(flags, methods, tally);
  if (!flags.json_out.empty()) writeFileAtomic(flags.json_out, tally.json.dump(2) + "\n");
  return deskewExitCode(flags, methods, tally);
}

}  // namespace

Command addDeskewCommand(CLI::App& app) {
  auto flags = std::make_shared<DeskewFlags>();
  auto* cli = app.add_subcommand(
      "deskew", "Remove lidar motion distortion; error against ground truth when there is one.");
  cli->footer(
      "Every method through one interface (algo/deskew, docs/deskew.md). --method all runs the\n"
      "methods that apply to the data (oracle needs ground truth, imu an IMU, odom-* odometry);\n"
      "the others are listed as not applicable. Never writes into DATASET: --out DIR gets a copy\n"
      "of the dataset plus deskewed_<method>.jsonl. Exit 3 when every method refused every\n"
      "scan, or with --strict when any scan was refused.");
  cli->add_option("DATASET", flags->dataset, "dataset directory (read only)")->required();
  std::vector<std::string> names = namesOf(algo::kDeskewMethodNames);
  names.emplace_back("all");
  cli->add_option("--method", flags->method, "de-skew method, or all: the ones that apply")
      ->check(oneOf("method", names))
      ->capture_default_str();
  cli->add_option("--stamps", flags->stamps,
                  "auto: put the stamps of a constant-rate stream (encoders, odometry, IMU, "
                  "scans) that are measurably jittered back on their grid (docs/deskew.md, "
                  "\"Jittered stamps\"); raw: use them as logged")
      ->check(oneOf("stamps", {"auto", "raw"}))
      ->capture_default_str();
  cli->add_option("--sync", flags->sync,
                  "auto: where the scans lag the wheels (sensor agreement of a first match of the "
                  "scans as measured), move the wheels and the gyro onto the scans' clock before "
                  "de-skewing, as calibrate and match --sync auto do (docs/deskew.md, \"Clock "
                  "sync\"); --out then holds the moved stamps; none: as logged")
      ->check(oneOf("sync", {"auto", "none"}))
      ->capture_default_str();
  cli->add_option("--reference", flags->reference, "time the corrected points describe")
      ->check(oneOf("reference", namesOf(algo::kReferenceTimeNames)))
      ->capture_default_str();
  cli->add_option("--geometry", flags->geometry,
                  "wheel geometry and lidar mount for odometry methods: nominal (default) or "
                  "true (a FILE here is the deprecated form of --calibration)");
  cli->add_option("--calibration", flags->calibration,
                  "use the geometry (and mount) of the best method in this `slamprep calibrate "
                  "--json` FILE");
  cli->add_option("--out", flags->out,
                  "write a copy of the dataset plus deskewed_<method>.jsonl into this new "
                  "directory (without it nothing is written)")
      ->check(outputPath());
  addJson(cli, *flags, "one object per method");
  addForce(cli, *flags, "an existing --out dataset or --json file");
  cli->add_option("--pieces", flags->quadratic_pieces, "odom-quadratic: linear pieces k")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  cli->add_option("--window", flags->window,
                  "only scans stamped in [T0, T1] count in the error figures (all are de-skewed)")
      ->expected(2);
  cli->add_flag("--stamp-is-last-beam", flags->stamp_is_last_beam,
                "the scans' stamps mark their last beam, not their first");
  addStrict(cli, *flags, "when any scan was refused, not only all");
  addQuiet(cli, *flags);
  cli->add_flag("--no-write", flags->no_write,
                "deprecated: nothing is written without --out; this drops --out");
  return {cli, [flags] { return runDeskew(*flags); }};
}

}  // namespace slamprep::app
