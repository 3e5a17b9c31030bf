#include "slamprep/app/common_flags.hpp"

#include "slamprep/app/outputs.hpp"

namespace slamprep::app {

CLI::Option* addForce(CLI::App* cli, CommonFlags& flags, const std::string& replaces) {
  return cli->add_flag("--force", flags.force,
                       "replace " + replaces +
                           "; the old stays until the new is complete; never an input, nor a "
                           "folder slamprep did not write");
}

CLI::Option* addStrict(CLI::App* cli, CommonFlags& flags, const std::string& when) {
  return cli->add_flag("--strict", flags.strict, "exit 3 " + when);
}

CLI::Option* addQuiet(CLI::App* cli, CommonFlags& flags) {
  return cli->add_flag("-q,--quiet", flags.quiet, "no progress output on stderr");
}

CLI::Option* addJson(CLI::App* cli, CommonFlags& flags, const std::string& writes) {
  return cli
      ->add_option("--json", flags.json_out,
                   "write to FILE, as JSON, " + writes + "; an existing FILE only with --force")
      ->type_name("FILE")
      ->check(outputPath());
}

}  // namespace slamprep::app
