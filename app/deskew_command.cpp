// `slamprep deskew`: lidar motion-distortion removal on a dataset, every method through one
// interface (algo/deskew), error against ground truth when the dataset has it (docs/deskew.md).
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>

#include "app/commands.hpp"
#include "core/atomic_file.hpp"
#include "core/dataset.hpp"
#include "core/error.hpp"
#include "core/odometry.hpp"
#include "eval/bench/dataset_deskew.hpp"
#include "eval/formats/dataset_io.hpp"
#include "eval/formats/scan_jsonl.hpp"

namespace slamprep::app {
namespace {

struct DeskewFlags {
  std::string dataset;
  std::string method = "all";
  std::string reference = "first";
  std::string geometry = "nominal";
  std::string out;
  std::string json_out;
  std::vector<double> window;  // --window T0 T1: scans whose stamp is inside count in the metrics
  bool stamp_is_last_beam = false;
  bool no_write = false;
  int quadratic_pieces = 4;
};

/// The wheel geometry and lidar mount the odometry-based methods use.
struct Geometry {
  DiffDriveParams wheels;
  SE2 T_base_lidar;
  std::string source;  ///< what the user asked for, for the printout
};

/// The calibration JSON's best method: ok entries only; those estimating the lidar mount first;
/// then the smallest sum of relative 1-sigmas of r_L, r_R, b (entries without sigma last).
Geometry geometryFromCalibration(const std::string& file, const Dataset& dataset) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(readFile(file));
  } catch (const nlohmann::json::exception& e) {
    throw InputError(file, std::string("not JSON: ") + e.what());
  }
  if (!j.is_array())
    throw InputError(file, "expected the array `slamprep calibrate --json` writes");
  const nlohmann::json* best = nullptr;
  auto rank = [](const nlohmann::json& e) {
    const bool mount = e.contains("lidar_x") && e["lidar_x"].is_number();
    double rel = 1e9;
    if (e.contains("sigma") && e["sigma"].is_object()) {
      const auto& s = e["sigma"];
      if (s.value("r_L", nlohmann::json()).is_number() && s["r_R"].is_number() &&
          s["b"].is_number())
        rel = s["r_L"].get<double>() / e["r_L"].get<double>() +
              s["r_R"].get<double>() / e["r_R"].get<double>() +
              s["b"].get<double>() / e["b"].get<double>();
    }
    return std::pair{mount ? 0 : 1, rel};
  };
  for (std::size_t i = 0; i < j.size(); ++i) {
    const auto& e = j[i];
    if (!e.is_object() || !e.value("ok", false)) continue;
    for (const char* key : {"r_L", "r_R", "b"})
      if (!e.contains(key) || !e[key].is_number() || !(e[key].get<double>() > 0.0))
        throw InputError(file + ": [" + std::to_string(i) + "]." + key, "must be a number > 0");
    if (!best || rank(e) < rank(*best)) best = &e;
  }
  if (!best) throw InputError(file, "no method with \"ok\": true");
  Geometry g;
  g.wheels = {(*best)["r_L"].get<double>(), (*best)["r_R"].get<double>(),
              (*best)["b"].get<double>()};
  g.T_base_lidar = dataset.info.T_base_lidar;
  if (best->contains("lidar_x") && (*best)["lidar_x"].is_number())
    g.T_base_lidar = SE2((*best)["lidar_x"].get<double>(), (*best)["lidar_y"].get<double>(),
                         (*best)["lidar_yaw"].get<double>());
  g.source = file + " (method " + best->value("method", std::string("?")) + ")";
  return g;
}

Geometry chooseGeometry(const DeskewFlags& flags, const Dataset& dataset) {
  if (flags.geometry == "nominal")
    return {dataset.info.nominal_geometry, dataset.info.T_base_lidar, "nominal"};
  if (flags.geometry == "true") {
    if (!dataset.info.true_geometry)
      throw InputError("--geometry true", flags.dataset + " has no true geometry (a real log?)");
    return {*dataset.info.true_geometry, dataset.info.T_base_lidar, "true"};
  }
  return geometryFromCalibration(flags.geometry, dataset);
}

using eval::ErrorStats;

struct MethodRun {
  algo::DeskewMethod method;
  eval::DatasetDeskew result;
  std::vector<ScanRecord> output;  ///< de-skewed scans; refused ones as measured
};

MethodRun runMethod(algo::DeskewMethod method, const Dataset& d, const PoseSeries& odometry,
                    const Geometry& geometry, const DeskewFlags& flags) {
  eval::DatasetDeskewOptions options;
  options.geometry = geometry.wheels;
  options.odometry = odometry;
  options.T_base_lidar = geometry.T_base_lidar;
  options.reference = *algo::parseReferenceTime(flags.reference);
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
      rec.T_world_base_true = d.groundtruth.at(r.reference_s);
      rec.T_odom_base_nominal = d.odom_nominal.at(r.reference_s);
    }
    run.output.push_back(std::move(rec));
  }
  return run;
}

nlohmann::ordered_json toJson(const MethodRun& run) {
  const auto& e = run.result.error_m;
  auto num = [&](const std::optional<ErrorStats>& stats, double ErrorStats::*field) {
    return stats ? nlohmann::ordered_json((*stats).*field) : nlohmann::ordered_json(nullptr);
  };
  return {{"method", std::string(algo::deskewMethodName(run.method))},
          {"mean_m", num(e, &ErrorStats::mean)},
          {"rms_m", num(e, &ErrorStats::rmse)},
          {"p95_m", num(e, &ErrorStats::p95)},
          {"max_m", num(e, &ErrorStats::max)},
          {"rotation_mean_m", num(run.result.rotation_induced_m, &ErrorStats::mean)},
          {"translation_mean_m", num(run.result.translation_induced_m, &ErrorStats::mean)},
          {"beams", e ? e->count : 0},
          {"seconds", run.result.seconds},
          {"scans", run.result.scans.size()},
          {"refused", run.result.refused}};
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
  std::cout << std::setprecision(4) << std::setw(10) << run.result.seconds << std::setw(9)
            << run.result.refused << "\n";
  if (!run.result.first_note.empty())
    std::cout << "    first note: " << run.result.first_note << "\n";
}

int runDeskew(const DeskewFlags& flags) {
  const Dataset d = eval::readDataset(flags.dataset);
  const Geometry geometry = chooseGeometry(flags, d);
  std::vector<algo::DeskewMethod> methods;
  if (flags.method == "all") {
    for (auto m : algo::allDeskewMethods())
      if (m != algo::DeskewMethod::kOracle || !d.groundtruth.empty()) methods.push_back(m);
  } else {
    const auto m = algo::parseDeskewMethod(flags.method);
    if (!m) throw InputError("--method", "unknown method \"" + flags.method + "\"");
    if (*m == algo::DeskewMethod::kOracle && d.groundtruth.empty())
      throw InputError("--method oracle", flags.dataset + " has no ground truth");
    methods.push_back(*m);
  }
  // Odometry for the chosen geometry: the dataset's own for nominal, else re-integrated.
  const PoseSeries odometry =
      geometry.source == "nominal" && !d.odom_nominal.empty()
          ? d.odom_nominal
          : integrateEncoders(d.encoders, geometry.wheels, d.info.ticks_per_revolution);
  if (odometry.empty())
    std::cerr << "deskew: " << flags.dataset << " has no odometry: odometry methods will refuse\n";
  std::filesystem::path out_dir = flags.out.empty() ? flags.dataset : flags.out;
  if (!flags.no_write && !flags.out.empty()) eval::writeDataset(out_dir, d);
  if (!flags.window.empty() && !(flags.window[0] <= flags.window[1]))
    throw InputError("--window", "T0 must not exceed T1");
  std::cout << "de-skew of " << d.scans.size() << " scans, reference " << flags.reference
            << ", geometry " << geometry.source << "\n"
            << std::left << std::setw(16) << "method" << std::right << std::setw(10) << "mean mm"
            << std::setw(10) << "rms mm" << std::setw(10) << "p95 mm" << std::setw(10) << "max mm"
            << std::setw(10) << "beams" << std::setw(10) << "seconds" << std::setw(9) << "refused"
            << "\n";
  nlohmann::ordered_json json = nlohmann::ordered_json::array();
  for (auto m : methods) {
    const MethodRun run = runMethod(m, d, odometry, geometry, flags);
    printRow(run);
    json.push_back(toJson(run));
    if (!flags.no_write) {
      const std::string name = "deskewed_" + std::string(algo::deskewMethodName(m)) + ".jsonl";
      writeFileAtomic(out_dir / name, eval::formatScans(run.output, (out_dir / name).string()));
    }
  }
  if (!flags.no_write)
    std::cout << "wrote deskewed_<method>.jsonl into " << out_dir.string() << "\n";
  if (!flags.json_out.empty()) writeFileAtomic(flags.json_out, json.dump(2) + "\n");
  return 0;
}

}  // namespace

Command addDeskewCommand(CLI::App& app) {
  auto flags = std::make_shared<DeskewFlags>();
  auto* cli = app.add_subcommand(
      "deskew", "Remove lidar motion distortion from a dataset's scans; error vs ground truth.");
  cli->add_option("DATASET", flags->dataset, "dataset directory")->required();
  std::vector<std::string> names = {"all"};
  for (auto m : algo::allDeskewMethods()) names.emplace_back(algo::deskewMethodName(m));
  cli->add_option("--method", flags->method, "de-skew method, or all")
      ->check(CLI::IsMember(names))
      ->capture_default_str();
  cli->add_option("--reference", flags->reference, "time the corrected points describe")
      ->check(CLI::IsMember({"first", "middle", "last"}))
      ->capture_default_str();
  cli->add_option("--geometry", flags->geometry,
                  "wheel geometry and lidar mount for odometry methods: nominal, true, or the "
                  "JSON `slamprep calibrate --json` wrote (its best method)")
      ->capture_default_str();
  cli->add_option("--out", flags->out, "write a copy of the dataset plus de-skewed scans here");
  cli->add_option("--json", flags->json_out, "write one object per method to FILE");
  cli->add_option("--pieces", flags->quadratic_pieces, "odom-quadratic: linear pieces k")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  cli->add_option("--window", flags->window,
                  "only scans stamped in [T0, T1] count in the error figures (all are de-skewed)")
      ->expected(2);
  cli->add_flag("--stamp-is-last-beam", flags->stamp_is_last_beam,
                "the scans' stamps mark their last beam, not their first");
  cli->add_flag("--no-write", flags->no_write, "only measure; write no de-skewed scans");
  return {cli, [flags] { return runDeskew(*flags); }};
}

}  // namespace slamprep::app
