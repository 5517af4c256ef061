// asf plan-eval: the unreliable-path-avoidance protocol of thesis Table 3.1 (ch. 3.5.1) on
// a SLAM run (asf/studies/plan_eval.h holds it; this file parses arguments and prints).
#include <asf/abi.h>
#include <asf/config.h>
#include <asf/errors.h>
#include <asf/studies/plan_eval.h>
#include <asf/framework/registry.h>
#include <tclap/CmdLine.h>

#include <iostream>

#include "commands.h"
#include "plugin_cli.h"

namespace asf::app {

int cmdPlanEval(int argc, char** argv) {
  TCLAP::CmdLine cmd(
      "Unreliable-path avoidance (thesis ch. 3.5.1, Table 3.1) on a SLAM run: for each "
      "feature-void zone and covariance factor of CONFIG.ini's [plan_eval] section, the "
      "zone's scans are ignored (its links become wheel odometry with the covariance times "
      "the factor, its loop closures go, nobody recognizes it), the graph is re-optimized, "
      "its marginals and cross-covariances recovered, place recognition estimated by Monte "
      "Carlo ICP on each node's scan, and every planner plans every start/goal pair of a "
      "node subset outside the zone. Error rate: share of the pairs whose path crosses the "
      "zone. Writes plan_eval.md, plan_eval.json (every chosen path), scenario_<X>.svg (thesis "
      "Fig. 3.4) and error_example_<X>.svg (Fig. 3.5: a baseline through the zone where expected "
      "uncertainty goes around, when one does); progress on stderr.",
      ' ', ASF_VERSION_STRING);
  TCLAP::UnlabeledValueArg<std::string> config("config", "The INI file", true, "", "CONFIG.ini",
                                               cmd);
  TCLAP::ValueArg<std::string> out_arg("o", "out", "Output folder (overrides [plan_eval] out)",
                                       false, "", "DIR", cmd);
  TCLAP::MultiArg<std::string> set("s", "set", "Override: section.key=value (repeatable)", false,
                                   "SECTION.KEY=VALUE", cmd);
  TCLAP::MultiArg<std::string> path("p", "plugin-path", "Extra plugin folder (repeatable)", false,
                                    "DIR", cmd);
  cmd.setExceptionHandling(false);
  cmd.parse(argc, argv);

  IniConfig ini = IniConfig::fromFile(config.getValue());
  for (const auto& s : set.getValue()) {
    if (s.find('.') == std::string::npos || s.find('.') > s.find('='))
      throw ConfigError("--set " + s + ": expected section.key=value");
    ini.applyOverride(s);
  }
  framework::Registry reg;
  scanPlugins(reg, path.getValue());
  const studies::PlanEvalOutput out =
      studies::runPlanEval(ini, reg, out_arg.getValue(), config.getValue());
  std::cout << out.markdown << "\nwrote " << out.md_file << " and " << out.json_file << "\n";
  return kOk;
}

}  // namespace asf::app
