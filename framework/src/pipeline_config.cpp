#include <asf/errors.h>
#include <asf/mapping/map3d.h>
#include <asf/mapping/map_builder.h>
#include <asf/framework/pipeline_config.h>
#include <asf/plugin.h>
#include <asf/mapping/topo_builder.h>

#include <cmath>
#include <filesystem>
#include <sstream>

namespace asf::framework {

namespace fs = std::filesystem;

namespace {

const KeySpec kPipelineKeys[] = {
    keyString("source", nullptr, "Source plugin: simulator or log (`asf plugins` lists them)"),
    keyString("frontend", nullptr, "Front-end plugin: frames -> pose-graph nodes and edges"),
    keyString("backend", "", "Back-end plugin: optimizes the graph, gives marginals (empty: none)"),
    keyString("segmenter", "", "Segmenter plugin: map -> regions (empty: none)"),
    keyString("planner", "", "Planner plugin: path between pose-graph nodes (empty: none)"),
    keyString("policy", "", "Exploration policy plugin; needs an active source (empty: none)"),
    keyInt("seed", "1", "Seed of every random draw of the run (each plugin gets its own stream)",
           0),
    keyString("plugin_path", "",
              "Extra plugin folders, ':'-separated, relative to this INI file's folder"),
    keyInt("max_steps", "100000", "Stop after this many source steps (0: no limit)", 0),
    keyDouble("max_distance", "0", "Stop after travelling this far [m] (0: no limit)", 0),
    keyInt("optimize_every", "1", "Run the back-end after this many new nodes", 1),
    keyBool("marginals", "true", "Recover marginal covariances after each optimization"),
    keyInt("segment_every", "1", "Segment every n-th map version", 1),
    keyInt("max_failed_goals", "50",
           "Stop when the policy's goals failed (unreachable/blocked) this many times in a row", 1),
    keyInt("max_idle_decisions", "200",
           "Stop when this many decisions in a row moved the robot less than 0.1 m in total "
           "(a policy going round in circles)",
           1),
    keyBool("timeline", "true",
            "Picture the run at each decision (timeline/NNNN.png: regions, graph, path, robot, "
            "goal) for report.html's timeline"),
    keyInt("timeline_max_side", "400", "Longer side of a timeline picture [px]", 50, 10000),
    keyBool("return_home", "false",
            "When the policy says done, drive back to the start (the first keyframe's estimate) "
            "and stop there; the stop reason says whether the robot got back"),
    keyDouble("progress_timeout_m", "0",
              "Stop when the explored area grew by less than progress_min_area over this many "
              "metres driven (0: off)",
              0),
    keyDouble("progress_timeout_s", "0",
              "Stop when the explored area grew by less than progress_min_area over this many "
              "seconds of the source's clock (0: off)",
              0),
    keyDouble("progress_min_area", "1", "New area [m^2] that counts as progress for the timeouts",
              0),
    keyPath("resume", "",
            "A run folder this run continues (asf run --resume sets it): its recorded log goes "
            "through the stages again, the policy retakes its recorded decisions, then the "
            "exploration goes on; needs a source that continues its recording (sim2d "
            "resume_from). Empty: a new run"),
    keyBool("map3d", "false",
            "Build the 3D map ([map3d]) from the frames' 3D observations at the keyframes; "
            "writes map3d.bt, map3d.ot, map3d.json, map3d_grid.png"),
    keyEnum("navigation_map", "scan2d", "scan2d|map3d|merged",
            "Grid the policy, navigation, segmenter and coverage use: the 2D scans' ([map]), "
            "the 3D map's projection, or both merged (an obstacle in either is one)"),
    keyDouble("progress_interval", "2.0", "Seconds between progress lines (0: none)", 0),
    keyDoubleList("snapshot_distances", "",
                  "Distances driven [m] at which the map, its regions and the topological graph "
                  "are saved to snapshots/ (thesis fig. 6.1; empty: none)",
                  0),
    keyEnum("verbosity", "INFO", "DEBUG|INFO|WARN|ERROR", "Log level of the host and plugins"),
};

const char* const kSlots[] = {"source", "frontend", "backend", "segmenter", "planner", "policy"};
const PluginKind kSlotKinds[] = {PluginKind::Source,    PluginKind::Frontend, PluginKind::Backend,
                                 PluginKind::Segmenter, PluginKind::Planner,  PluginKind::Policy};

void appendSection(std::ostringstream& os, const std::string& name, const Params& p,
                   const KeySpec* keys, std::size_t n, const std::string& title) {
  os << "\n; " << title << "\n[" << name << "]\n";
  for (std::size_t i = 0; i < n; ++i) {
    const KeySpec& k = keys[i];
    if (!p.has(k.name)) continue;
    os << "; " << k.doc << " (" << keyTypeName(k.type);
    if (k.type == KeyType::Enum && k.choices) os << ": " << k.choices;
    if (!std::isinf(k.min) || !std::isinf(k.max))
      os << ", range [" << k.min << ", " << k.max << "]";
    os << (p.isDefault(k.name) ? ", default" : ", set") << ")\n";
    os << k.name << " = " << p.getString(k.name) << "\n";
  }
}

}  // namespace

const KeySpec* pipelineKeys(std::size_t& n) {
  n = std::size(kPipelineKeys);
  return kPipelineKeys;
}

std::vector<FrameworkSection> frameworkSections() {
  std::vector<FrameworkSection> v;
  std::size_t n;
  const KeySpec* k = pipelineKeys(n);
  v.push_back({"pipeline", k, n});
  k = mapping::MapBuilder::keys(n);
  v.push_back({"map", k, n});
  k = mapping::TopoBuilder::keys(n);
  v.push_back({"topology", k, n});
  k = mapping::Map3d::keys(n);
  v.push_back({"map3d", k, n});
  return v;
}

std::string ResolvedConfig::toIni() const {
  std::ostringstream os;
  os << "; asf configuration, resolved: every key with its value or default.\n";
  const auto fw = frameworkSections();
  appendSection(os, "pipeline", pipeline, fw[0].keys, fw[0].num_keys, "framework: the pipeline");
  appendSection(os, "map", map, fw[1].keys, fw[1].num_keys, "framework: occupancy grid builder");
  appendSection(os, "topology", topology, fw[2].keys, fw[2].num_keys,
                "framework: topological graph builder");
  appendSection(os, "map3d", map3d, fw[3].keys, fw[3].num_keys,
                "framework: 3D map (OctoMap), used with [pipeline] map3d = true");
  for (const char* slot : kSlots) {
    auto it = slots.find(slot);
    if (it == slots.end()) continue;
    const PluginInfo& info = *it->second;
    const auto& d = *info.descriptor;
    appendSection(os, d.name, plugin_params.at(d.name), d.keys, d.num_keys,
                  std::string(slot) + " plugin '" + d.name + "' " + d.version + ": " +
                      d.description + " (" + info.file + ")");
  }
  return os.str();
}

namespace {

/// resolveConfig's steps; every error is collected, so one run of `asf config` names them all.
class ConfigResolver {
 public:
  ConfigResolver(const IniConfig& ini, Registry& registry) : ini_(ini), registry_(registry) {}

  ResolvedConfig resolve() {
    resolveFrameworkSections();
    scanPluginFolders();
    findSlotPlugins();
    checkOtherSections();
    for (const auto& [slot, info] : rc_.slots) {
      attempt([&, &info = info] {
        rc_.plugin_params[info->name()] =
            ini_.resolve(info->name(), info->descriptor->keys, info->descriptor->num_keys);
      });
    }
    if (!errors_.empty()) {
      std::string msg;
      for (const auto& e : errors_) msg += (msg.empty() ? "" : "\n") + e;
      throw ConfigError(msg);
    }
    return rc_;
  }

 private:
  template <class Fn>
  void attempt(Fn&& fn) {
    try {
      fn();
    } catch (const Error& e) {
      errors_.push_back(e.what());
    }
  }

  void resolveFrameworkSections() {
    attempt([&] { rc_.pipeline = ini_.resolve("pipeline", fw_[0].keys, fw_[0].num_keys); });
    attempt([&] { rc_.map = ini_.resolve("map", fw_[1].keys, fw_[1].num_keys); });
    attempt([&] { rc_.topology = ini_.resolve("topology", fw_[2].keys, fw_[2].num_keys); });
    attempt([&] { rc_.map3d = ini_.resolve("map3d", fw_[3].keys, fw_[3].num_keys); });
    attempt([&] {
      const Params& p = rc_.pipeline;
      if (p.has("navigation_map") && p.getString("navigation_map") != "scan2d" &&
          !p.getBool("map3d"))
        p.fail("navigation_map", "'" + p.getString("navigation_map") +
                                     "' needs the 3D map: set [pipeline] map3d = true");
    });
    if (!ini_.hasSection("pipeline"))
      errors_.insert(errors_.begin(), ini_.fileName() + ": no [pipeline] section");
  }

  /// Slots and plugin_path are read from the INI directly, so their errors are reported
  /// even when another [pipeline] key is invalid.
  void scanPluginFolders() {
    for (const auto& d : Registry::defaultSearchPath()) registry_.scanDirectory(d);
    std::stringstream ss(ini_.get("pipeline", "plugin_path"));
    std::string d;
    while (std::getline(ss, d, ':')) {
      if (d.empty()) continue;
      fs::path p(d);
      if (p.is_relative() && !ini_.baseDir().empty()) p = fs::path(ini_.baseDir()) / p;
      if (!fs::is_directory(p))
        errors_.push_back(ini_.where("pipeline", "plugin_path") + ": [pipeline] plugin_path: '" +
                          p.string() + "' is not a folder");
      registry_.scanDirectory(p.string());
    }
  }

  void findSlotPlugins() {
    for (std::size_t i = 0; i < std::size(kSlots); ++i) {
      const std::string name = ini_.get("pipeline", kSlots[i]);
      if (name.empty()) continue;
      try {
        rc_.slots[kSlots[i]] = registry_.find(name, kSlotKinds[i]);
      } catch (const PluginError& e) {
        errors_.push_back(ini_.where("pipeline", kSlots[i]) + ": [pipeline] " + kSlots[i] + ": " +
                          e.what());
      }
    }
    if (rc_.slots.count("policy") && rc_.slots.count("source") && !rc_.slots.count("segmenter"))
      rc_.warnings.push_back(
          "[pipeline] a policy without a segmenter sees a topological graph "
          "with no regions");
  }

  /// A section of a plugin the pipeline does not use is validated and warned about; a section
  /// of no plugin is an error naming the closest known section.
  void checkOtherSections() {
    std::vector<std::string> known_sections;
    for (const auto& s : fw_) known_sections.push_back(s.name);
    for (const auto& p : registry_.plugins()) known_sections.push_back(p->name());
    for (const auto& section : ini_.sections()) {
      bool framework = false;
      for (const auto& s : fw_) framework = framework || section == s.name;
      if (framework) continue;
      bool selected = false;
      for (const auto& [slot, info] : rc_.slots) selected = selected || info->name() == section;
      if (selected) continue;
      std::shared_ptr<const PluginInfo> other;
      try {
        other = registry_.find(section);
      } catch (const PluginError&) {
      }
      if (other) {
        // Validated all the same, so a typo waits for no one to switch plugins.
        attempt(
            [&] { ini_.resolve(section, other->descriptor->keys, other->descriptor->num_keys); });
        rc_.warnings.push_back(ini_.where(section) + ": [" + section + "] configures plugin '" +
                               section + "', which this pipeline does not use");
        continue;
      }
      errors_.push_back(ini_.unknownSection(
          section, known_sections,
          "sections are [pipeline], [map], [topology], [map3d] and one per plugin, named after "
          "it"));
    }
  }

  const IniConfig& ini_;
  Registry& registry_;
  const std::vector<FrameworkSection> fw_ = frameworkSections();
  ResolvedConfig rc_;
  std::vector<std::string> errors_;
};

}  // namespace

ResolvedConfig resolveConfig(const IniConfig& ini, Registry& registry) {
  return ConfigResolver(ini, registry).resolve();
}

}  // namespace asf::framework
