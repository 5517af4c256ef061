#include <asf/framework/pipeline.h>
#include <tclap/CmdLine.h>

#include <iostream>

#include "commands.h"

namespace asf::app {

int cmdConfig(int argc, char** argv) {
  TCLAP::CmdLine cmd(
      "Prints CONFIG resolved: every section the pipeline uses with every key, its value or "
      "default, type, range and doc. Validates it like `asf run` does.",
      ' ', ASF_VERSION_STRING);
  TCLAP::UnlabeledValueArg<std::string> config("config", "Pipeline INI file", true, "",
                                               "CONFIG.ini", cmd);
  TCLAP::MultiArg<std::string> set("s", "set", "Override a key: section.key=value (repeatable)",
                                   false, "section.key=value", cmd);
  cmd.setExceptionHandling(false);
  cmd.parse(argc, argv);

  IniConfig ini = IniConfig::fromFile(config.getValue());
  for (const auto& s : set.getValue()) ini.applyOverride(s);
  framework::Registry reg;
  const framework::ResolvedConfig rc = framework::resolveConfig(ini, reg);
  for (const auto& w : rc.warnings) std::cerr << "warning: " << w << "\n";
  std::cout << rc.toIni();
  return kOk;
}

}  // namespace asf::app
