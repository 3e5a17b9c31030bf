// Slip against Bullet's solver settings: for every shipped scenario in room.yaml, the largest
// position error of wheel odometry integrated with the TRUE geometry (slip + tick quantisation,
// SimSummary::drift_true.max_position_error_m), for solver iterations x contact relaxation, plus
// the CPU time of the figure eight with the full sensor set. Not a test: it prints a table for
// docs/simulate.md and results/benchmarks.md.
// With STARTS > 1 every cell is the mean over that many start poses (seeds 1..STARTS, start
// jitter +-5 cm and +-5 deg): one run's slip is a chaotic draw (neighbouring settings differ by
// 1 mm), so settings are compared by the mean, and the last column averages all scenarios.
// Run: sim_slip_table [iterations,...] [relaxation,...] [physics_rate_hz,...] [STARTS]
//      (defaults: 50,30,20,15,12,10; 1,1.5; 1000; 1)

#include <cstdio>
#include <ctime>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "slamprep/sim/drive/simulator.hpp"

namespace {

std::vector<double> parseList(const char* text, std::vector<double> fallback) {
  if (text == nullptr) return fallback;
  std::vector<double> out;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');) out.push_back(std::stod(item));
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace slamprep::sim;
  const std::filesystem::path root(SLAMPREP_SOURCE_DIR);
  const std::vector<double> iterations =
      parseList(argc > 1 ? argv[1] : nullptr, {50, 30, 20, 15, 12, 10});
  const std::vector<double> relaxations = parseList(argc > 2 ? argv[2] : nullptr, {1.0, 1.5});
  const std::vector<double> rates = parseList(argc > 3 ? argv[3] : nullptr, {1000.0});
  const int starts = argc > 4 ? std::stoi(argv[4]) : 1;
  const std::vector<std::string> scenarios = {"figure_eight",  "arc",  "umbmark_ccw", "umbmark_cw",
                                              "random_smooth", "spin", "stop_and_go", "default"};
  const World world = loadWorld(root / "worlds" / "room.yaml");
  std::vector<Scenario> loaded;
  for (const std::string& name : scenarios)
    loaded.push_back(loadScenario(root / "worlds" / "scenarios" / (name + ".yaml")));

  std::printf(
      "| physics rate (Hz) | iterations | relaxation | figure-eight CPU (s) | real-time factor |");
  for (const std::string& name : scenarios) std::printf(" %s (mm) |", name.c_str());
  std::printf(" mean (mm) |\n");
  for (const double rate : rates)
    for (const double relaxation : relaxations)
      for (const double iters : iterations) {
        const ScenePhysicsParams physics{static_cast<int>(iters), relaxation};
        SimConfig config;
        config.physics_rate_hz = rate;
        std::printf("| %.0f | %d | %.2f |", rate, physics.solver_iterations, relaxation);
        double cpu_s = 0.0, sim_s = 0.0, total_mm = 0.0;
        std::string row;
        for (std::size_t k = 0; k < scenarios.size(); ++k) {
          double sum_mm = 0.0;
          for (int s = 1; s <= starts; ++s) {
            SimConfig run = config;
            if (starts > 1) run.start_jitter = {0.05, 5.0};
            run.seed = static_cast<std::uint64_t>(s);
            const std::clock_t start = std::clock();
            const SimResult result = simulate(run, world, loaded[k], {}, physics);
            if (k == 0 && s == 1) {
              cpu_s = static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC;
              sim_s = result.summary.duration_s;
            }
            sum_mm += result.summary.drift_true.max_position_error_m * 1e3;
          }
          char cell[32];
          std::snprintf(cell, sizeof cell, " %.2f |", sum_mm / starts);
          row += cell;
          total_mm += sum_mm / starts;
        }
        std::printf(" %.3f | %.0f |%s %.2f |\n", cpu_s, sim_s / cpu_s, row.c_str(),
                    total_mm / static_cast<double>(scenarios.size()));
        std::fflush(stdout);
      }
  return 0;
}
