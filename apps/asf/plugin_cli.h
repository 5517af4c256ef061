#pragma once
// What the commands that load one plugin by name share: the plugin search, --set arguments
// validated as INI overrides, plugin log lines on stderr (stdout stays the report).
#include <asf/config.h>
#include <asf/plugin.h>
#include <asf/framework/registry.h>
#include <asf/text.h>

#include <chrono>
#include <string>
#include <vector>

namespace asf::app {

/// Scans the default plugin folders, then `extra` (--plugin-path).
void scanPlugins(framework::Registry& reg, const std::vector<std::string>& extra);

/// --set arguments as INI overrides: "key=value" goes to [plugin], "section.key=value" to
/// that section, which must be the plugin's (any case) or one of `extra_sections`; anything
/// else is a ConfigError "--set A: the <what> is 'plugin', not 'section'" followed by `hint`.
/// Resolve the result with IniConfig::resolve, which reports unknown keys.
IniConfig setOverrides(const std::vector<std::string>& sets, const std::string& plugin,
                       const std::string& what, const std::vector<std::string>& extra_sections = {},
                       const std::string& hint = "");

// Plugin log lines on stderr: asf::framework::logPluginToStderr (registry.h); lowercase and
// secondsSince: asf/text.h.

}  // namespace asf::app
