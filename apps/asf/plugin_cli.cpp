#include "plugin_cli.h"

#include <asf/errors.h>

#include <algorithm>
#include <cctype>

namespace asf::app {

void scanPlugins(framework::Registry& reg, const std::vector<std::string>& extra) {
  for (const auto& d : framework::Registry::defaultSearchPath()) reg.scanDirectory(d);
  for (const auto& d : extra) reg.scanDirectory(d);
}

IniConfig setOverrides(const std::vector<std::string>& sets, const std::string& plugin,
                       const std::string& what, const std::vector<std::string>& extra_sections,
                       const std::string& hint) {
  IniConfig ini = IniConfig::fromText("", "--set");
  for (const auto& a : sets) {
    const auto eq = a.find('='), dot = a.find('.');
    if (eq == std::string::npos) throw ConfigError("--set " + a + ": expected key=value");
    const bool has_section = dot != std::string::npos && dot < eq;
    if (has_section) {
      const std::string section = lowercase(a.substr(0, dot));
      const bool extra =
          std::find(extra_sections.begin(), extra_sections.end(), section) != extra_sections.end();
      if (!extra && section != lowercase(plugin))
        throw ConfigError("--set " + a + ": the " + what + " is '" + plugin + "', not '" +
                          a.substr(0, dot) + "'" + hint);
    }
    ini.applyOverride(has_section ? a : plugin + "." + a);
  }
  return ini;
}

}  // namespace asf::app
