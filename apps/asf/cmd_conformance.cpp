#include <asf/conformance.h>
#include <tclap/CmdLine.h>

#include <cstring>
#include <iostream>
#include <optional>

#include "commands.h"

namespace asf::app {

int cmdConformance(int argc, char** argv) {
  // GoogleTest's own flags (--gtest_filter=..., --gtest_output=...) pass through to the kit.
  std::vector<char*> ours, gtest_args{argv[0]};
  for (int i = 0; i < argc; ++i)
    (i > 0 && std::strncmp(argv[i], "--gtest", 7) == 0 ? gtest_args : ours).push_back(argv[i]);

  TCLAP::CmdLine cmd(
      "Runs the conformance kit (the contract of each plugin kind) on plugins given as files "
      "(*.so) or names (searched like `asf plugins`). GoogleTest flags (--gtest_filter=...) "
      "pass through. Exit code 0: all passed; 3: a test failed.",
      ' ', ASF_VERSION_STRING);
  TCLAP::UnlabeledMultiArg<std::string> targets("plugins", "Plugin files or names", false,
                                                "PLUGIN.so|NAME", cmd);
  TCLAP::SwitchArg all("a", "all", "Every plugin found", cmd);
  TCLAP::MultiArg<std::string> path("p", "plugin-path", "Extra plugin folder (repeatable)", false,
                                    "DIR", cmd);
  TCLAP::ValueArg<std::string> config(
      "c", "config",
      "INI with a section per plugin name: values the kit configures that plugin with (keys "
      "it cannot make up, e.g. a log source's file); relative paths from the INI's folder",
      false, "", "FILE.ini", cmd);
  cmd.setExceptionHandling(false);
  cmd.parse(static_cast<int>(ours.size()), ours.data());

  std::vector<std::shared_ptr<const framework::PluginInfo>> plugins;
  framework::Registry reg;
  bool scanned = false;
  auto scan = [&] {
    if (scanned) return;
    scanned = true;
    for (const auto& d : framework::Registry::defaultSearchPath()) reg.scanDirectory(d);
    for (const auto& d : path.getValue()) reg.scanDirectory(d);
  };
  for (const auto& t : targets.getValue()) {
    if (t.find('/') != std::string::npos || (t.size() > 3 && t.substr(t.size() - 3) == ".so")) {
      plugins.push_back(framework::Registry::loadFile(t));
    } else {
      scan();
      auto p = reg.find(t);
      if (!p) {
        std::string avail;
        for (const auto& q : reg.plugins()) avail += (avail.empty() ? "" : ", ") + q->name();
        throw PluginError("unknown plugin '" + t +
                          "'; available: " + (avail.empty() ? "(none)" : avail));
      }
      plugins.push_back(p);
    }
  }
  if (all.getValue()) {
    scan();
    for (const auto& p : reg.plugins()) plugins.push_back(p);
  }
  if (plugins.empty()) {
    std::cerr << "asf conformance: name at least one plugin, or --all (asf conformance --help)\n";
    return kUsage;
  }
  std::optional<IniConfig> ini;
  if (!config.getValue().empty()) ini = IniConfig::fromFile(config.getValue());
  int n = static_cast<int>(gtest_args.size());
  gtest_args.push_back(nullptr);
  const int rc = conformance::run(plugins, n, gtest_args.data(), ini ? &*ini : nullptr);
  return rc == 0 ? kOk : kTestsFailed;
}

}  // namespace asf::app
