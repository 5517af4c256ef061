#pragma once
/// \file pipeline_config.h
/// A pipeline's INI file resolved against the framework's key tables ([pipeline], [map],
/// [topology], [map3d]) and the key tables of the plugins its slots name.
#include <asf/config.h>
#include <asf/framework/registry.h>

#include <map>
#include <memory>
#include <string>
#include <vector>

namespace asf::framework {

/// Keys of the [pipeline] section.
const KeySpec* pipelineKeys(std::size_t& n);
/// Framework-owned sections and their key tables (pipeline, map, topology, map3d).
struct FrameworkSection {
  const char* name;
  const KeySpec* keys;
  std::size_t num_keys;
};
std::vector<FrameworkSection> frameworkSections();

/// A pipeline's configuration resolved against the framework's and the plugins' key tables.
struct ResolvedConfig {
  Params pipeline, map, topology, map3d;
  /// slot name -> plugin (empty slots absent)
  std::map<std::string, std::shared_ptr<const PluginInfo>> slots;
  std::map<std::string, Params> plugin_params;  ///< plugin name -> its section's values
  std::vector<std::string> warnings;
  /// The whole configuration as INI text, every default filled in and commented.
  std::string toIni() const;
};

/// Scans the default search path plus [pipeline] plugin_path into `registry`, then validates
/// every section. Throws ConfigError listing all problems (unknown sections/keys with "did
/// you mean", missing required keys, bad values, unknown plugins).
ResolvedConfig resolveConfig(const IniConfig& ini, Registry& registry);

}  // namespace asf::framework
