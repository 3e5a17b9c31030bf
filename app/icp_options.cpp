#include "slamprep/app/icp_options.hpp"

#include "slamprep/app/choices.hpp"

namespace slamprep::app {

void addIcpOptions(CLI::App* cli, algo::IcpParams& icp) {
  cli->add_option("--max-iterations", icp.max_iterations, "ICP rounds per match")
      ->check(positive())
      ->capture_default_str();
  cli->add_option("--max-correspondence-distance", icp.max_correspondence_distance_m,
                  "ICP gating: farther pairs (m) are no correspondence")
      ->check(positive())
      ->capture_default_str();
  cli->add_option("--outlier-sigmas", icp.outlier_sigmas,
                  "ICP robust gate: pairs beyond this many robust sigmas (1.4826 x median "
                  "residual) are dropped each round; 0 = off")
      ->check(nonNegative())
      ->capture_default_str();
  cli->add_option("--trim", icp.trim_fraction,
                  "ICP trimming: this fraction of the remaining pairs, the worst, is dropped")
      ->check(CLI::Range(0.0, 0.9))
      ->capture_default_str();
  cli->add_option(
         "--line-thickness", icp.line_max_thickness,
         "ICP: a point's neighbours are a line when sqrt(lambda_min / lambda_max) is below this")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
}

}  // namespace slamprep::app
