// asf segment: one map image through a segmenter plugin (label PNG, topological graph,
// overlay). asf segment-eval: a segmenter scored on the room segmentation benchmark as
// ../shared/docs/roomseg-eval.md describes (the figures of docs/benchmarks/segmentation.md).
#include <asf/abi.h>
#include <asf/atomic_file.h>
#include <asf/config.h>
#include <asf/errors.h>
#include <asf/io/occupancy_io.h>
#include <asf/framework/registry.h>
#include <asf/evaluation/run_report.h>
#include <asf/studies/segment_benchmark.h>
#include <asf/evaluation/segmentation_eval.h>
#include <asf/segmenter.h>
#include <asf/text.h>
#include <asf/mapping/topo_builder.h>
#include <tclap/CmdLine.h>

#include <cctype>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "commands.h"
#include "plugin_cli.h"

namespace asf::app {

namespace {

namespace fs = std::filesystem;

/// A segmenter plugin with its validated keys, and the [topology] keys; creates a fresh,
/// configured instance per map (segmenters keep id state between calls).
struct SegmenterSetup {
  std::shared_ptr<const framework::PluginInfo> info;
  Params params, topology;

  framework::PluginHandle<Segmenter> create() const {
    auto s = framework::Registry::create<Segmenter>(info);
    framework::logPluginToStderr(*s, info->name());
    s->configure(params, PluginContext{});
    return s;
  }
};

const char* kSetHelp =
    "Segmenter key: key=value or <segmenter>.key=value; topological graph key: "
    "topology.key=value (min_border_width, min_frontier_width, unknown_band). Repeatable";

SegmenterSetup setupSegmenter(const std::string& name, const std::vector<std::string>& sets,
                              const std::vector<std::string>& plugin_paths, bool with_topology) {
  framework::Registry reg;
  scanPlugins(reg, plugin_paths);
  SegmenterSetup s;
  s.info = reg.find(name, PluginKind::Segmenter);
  const std::string plugin = s.info->name();
  if (!with_topology)
    for (const auto& a : sets)
      if (lowercase(a).rfind("topology.", 0) == 0)
        throw ConfigError("--set " + a + ": no topological graph here (asf segment has one)");
  const IniConfig ini = setOverrides(
      sets, plugin, "segmenter",
      with_topology ? std::vector<std::string>{"topology"} : std::vector<std::string>{},
      with_topology ? " (topology.key=value for the graph)" : "");
  s.params = ini.resolve(plugin, s.info->descriptor->keys, s.info->descriptor->num_keys);
  std::size_t n = 0;
  const KeySpec* topo_keys = mapping::TopoBuilder::keys(n);
  s.topology = ini.resolve("topology", topo_keys, n);
  return s;
}

void writeTextAtomically(const std::string& path, const std::string& text) {
  writeFileAtomically(path, text);
}

}  // namespace

int cmdSegment(int argc, char** argv) {
  TCLAP::CmdLine cmd(
      "Segments one map into regions with a segmenter plugin. A map image is read as the "
      "room segmentation benchmark does: 8-bit grayscale, pixel >= --free-threshold is free, "
      "anything else occupied, origin (0, 0), image row 0 at the top (max y); a ROS "
      "map_server YAML (MAP.yaml) brings its resolution, origin, thresholds and mode, and "
      "its unknown cells stay unknown (not free). Writes a 16-bit "
      "single-channel label PNG (0 = no region, else the region id; same size and "
      "orientation as the input), optionally the topological graph (JSON as asf run's "
      "topology.json) and an overlay image (regions, ids, graph edges).",
      ' ', ASF_VERSION_STRING);
  TCLAP::UnlabeledValueArg<std::string> map_arg("map", "Map image or map_server YAML", true, "",
                                                "MAP.png|MAP.yaml", cmd);
  TCLAP::ValueArg<double> res("r", "resolution", "Metres per pixel", false, 0.05, "M", cmd);
  TCLAP::ValueArg<std::string> segmenter("g", "segmenter", "Segmenter plugin name", true, "",
                                         "NAME", cmd);
  TCLAP::ValueArg<std::string> out("o", "output", "Label image to write (16-bit PNG)", true, "",
                                   "LABELS.png", cmd);
  TCLAP::ValueArg<std::string> graph("", "graph", "Write the topological graph (JSON)", false, "",
                                     "OUT.json", cmd);
  TCLAP::ValueArg<std::string> overlay(
      "", "overlay",
      "Write an overlay image: PNG, or SVG (graph as vectors) when the name ends in .svg", false,
      "", "OUT.png", cmd);
  TCLAP::ValueArg<int> threshold("t", "free-threshold", "Pixels >= this are free", false,
                                 io::kBenchmarkFreeThreshold, "0-255", cmd);
  TCLAP::MultiArg<std::string> set("s", "set", kSetHelp, false, "KEY=VALUE", cmd);
  TCLAP::MultiArg<std::string> path("p", "plugin-path", "Extra plugin folder (repeatable)", false,
                                    "DIR", cmd);
  cmd.setExceptionHandling(false);
  cmd.parse(argc, argv);
  if (!(res.getValue() > 0)) throw ConfigError("--resolution must be > 0");

  const SegmenterSetup setup =
      setupSegmenter(segmenter.getValue(), set.getValue(), path.getValue(), true);
  // A map_server YAML brings its resolution, origin and free/occupied/unknown rules.
  const bool yaml = io::isOccupancyYaml(map_arg.getValue());
  if (yaml && (res.isSet() || threshold.isSet()))
    throw ConfigError(map_arg.getValue() + ": a map_server YAML sets the resolution and the " +
                      "free cells; leave out " +
                      (res.isSet() ? "--resolution" : "--free-threshold"));
  const io::GrayImage image = io::readGrayImage(
      yaml ? io::occupancyImagePath(map_arg.getValue(), io::readOccupancyYaml(map_arg.getValue()))
           : map_arg.getValue());
  const GridMap map = yaml ? io::readOccupancyMap(map_arg.getValue())
                           : io::gridFromImage(image, res.getValue(), threshold.getValue());
  auto seg = setup.create();
  const auto t0 = std::chrono::steady_clock::now();
  Segmentation s;
  try {
    s = seg->segment(map, nullptr);
  } catch (const InputError& e) {  // name the file the map came from
    throw InputError(map_arg.getValue() + ": " + e.what());
  }
  const double ms = msSince(t0);
  io::writeLabelImage(out.getValue(), studies::segmentationRaster(s, image, map_arg.getValue()));

  mapping::TopoBuilder topo;
  topo.configure(setup.topology);
  topo.update(s, map);
  if (!graph.getValue().empty())
    writeTextAtomically(graph.getValue(), graph::topologyJson(topo.graph()));
  if (!overlay.getValue().empty())
    evaluation::writeSegmentationOverlay(overlay.getValue(), map, s, &topo.graph());

  std::size_t frontier = 0;
  for (const auto& e : topo.graph().edges) frontier += e.frontier();
  std::cout << map_arg.getValue() << ": " << image.width << " x " << image.height << " px, "
            << s.regions.size() << " regions, " << topo.graph().edges.size() - frontier
            << " edges, " << frontier << " frontier edges; " << setup.info->name() << " in "
            << std::fixed << std::setprecision(1) << ms << " ms\nwrote " << out.getValue();
  if (!graph.getValue().empty()) std::cout << ", " << graph.getValue();
  if (!overlay.getValue().empty()) std::cout << ", " << overlay.getValue();
  std::cout << "\n";
  return kOk;
}

namespace {

using MapResult = studies::BenchmarkMapResult;

/// Scores every map, writing the JSON report after each; the report on stdout. An error
/// keeps what was scored (kError).
int scoreBenchmark(const SegmenterSetup& setup, const studies::SegmentBenchmarkOptions& o,
                   const std::vector<std::string>& only, const std::string& json_out) {
  const std::string name = setup.info->name();
  const std::vector<std::string> names = studies::benchmarkMapNames(o, only);
  if (!o.images_dir.empty()) fs::create_directories(o.images_dir);

  std::vector<MapResult> results;
  std::string error, current;  // current: the map and variant being scored, for errors
  const std::string protocol = o.incremental ? o.exploration : "";
  auto save = [&] {
    if (!json_out.empty())
      writeTextAtomically(json_out, studies::benchmarkReportJson(results, name, setup.params,
                                                                 protocol, error));
  };
  try {
    for (std::size_t k = 0; k < names.size(); ++k)
      studies::scoreBenchmarkMap(
          names[k],
          "[" + std::to_string(k + 1) + "/" + std::to_string(names.size()) + "] " + names[k], o,
          [&] { return setup.create(); },
          [](const std::string& line) { std::cerr << line << "\n"; }, results, current, save);
  } catch (const std::exception& e) {
    // Keep what was scored: the report and the JSON cover the maps done before the error.
    error = (current.empty() ? "" : current + ": ") + e.what();
  }
  std::cout << studies::benchmarkReportText(results);
  try {
    save();
  } catch (const std::exception& e) {
    std::cerr << "asf segment-eval: error: " << e.what() << "\n";
    return kError;
  }
  if (!json_out.empty()) std::cout << "wrote " << json_out << "\n";
  if (!error.empty()) {
    std::cerr << "asf segment-eval: error: " << error << " (" << results.size()
              << " map scores kept above" << (json_out.empty() ? "" : " and in the JSON") << ")\n";
    return kError;
  }
  return kOk;
}

/// asf segment-eval's options, added to `cmd` in declaration order (--help's order depends on it).
struct SegmentEvalArgs {
  explicit SegmentEvalArgs(TCLAP::CmdLine& parser) : cmd(parser) {}

  TCLAP::CmdLine& cmd;
  TCLAP::ValueArg<std::string> plain{"", "plain", "Folder of the plain maps (<name>.png)", true, "",
                                     "DIR", cmd};
  TCLAP::ValueArg<std::string> gt{
      "", "gt", "Folder of the ground truth (<name>_gt_segmentation.png)", true, "", "DIR", cmd};
  TCLAP::ValueArg<std::string> furnished{"", "furnished",
                                         "Folder of the furnished maps (<name>_furnitures.png)",
                                         false, "", "DIR", cmd};
  TCLAP::ValueArg<double> res{"r", "resolution", "Metres per pixel", false, 0.05, "M", cmd};
  TCLAP::ValueArg<std::string> segmenter{"g", "segmenter", "Segmenter plugin name", true, "",
                                         "NAME", cmd};
  TCLAP::MultiArg<std::string> set{"s", "set",
                                   "Segmenter key: key=value or <segmenter>.key=value "
                                   "(repeatable)",
                                   false, "KEY=VALUE", cmd};
  TCLAP::MultiArg<std::string> path{"p", "plugin-path", "Extra plugin folder (repeatable)", false,
                                    "DIR", cmd};
  TCLAP::MultiArg<std::string> only{"m", "map", "Score only this map name (repeatable)", false,
                                    "NAME", cmd};
  TCLAP::ValueArg<std::string> json_out{"j", "json",
                                        "Write the JSON report here: segmenter, params, maps "
                                        "[{name, variant, precision, recall, precision_pooled, "
                                        "recall_pooled, mcc, segments, rooms, time_ms, "
                                        "incremental}], summary {plain, furnished: <key>_mean, "
                                        "<key>_std, incremental}, complete, error. Rewritten "
                                        "after every map: an error or interruption keeps what "
                                        "was done",
                                        false, "", "OUT.json", cmd};
  TCLAP::ValueArg<std::string> images{"i", "images",
                                      "Write overlays <name>_<variant>.png (regions, ids, "
                                      "ground-truth room outlines in dark red) and 16-bit label "
                                      "images <name>_<variant>_labels.png into this folder",
                                      false, "", "DIR", cmd};
  TCLAP::ValueArg<std::string> reference{
      "", "reference",
      "Folder of the reference DuDe's own outputs (one colour per region, black none: "
      "<name>_DuDe.png, <name>_DuDe_furnitures.png; with --incremental <name>_Inc.png, "
      "<name>_Inc_furnitures.png): each segmentation is compared with its counterpart region "
      "by region (area-weighted best-match IoU, adjusted Rand index) and the reference is "
      "scored as the segmenter is",
      false, "", "DIR", cmd};
  TCLAP::SwitchArg incremental{"", "incremental",
                               "Also time incremental segmentation while each map is revealed "
                               "step by step (--exploration, --incremental-on)",
                               cmd};
  std::vector<std::string> explorations{"frontier", "raster_disks"};
  TCLAP::ValuesConstraint<std::string> exploration_values{explorations};
  TCLAP::ValueArg<std::string> exploration{
      "", "exploration",
      "How --incremental reveals a map: frontier (a simulated laser, --sensor-range, "
      "--scan-spacing) or raster_disks (the thesis' evaluation: disks of 100 px every 50 px "
      "along rows, seen through walls; a segmentation after every disk once 160 free px are "
      "revealed)",
      false, "frontier", &exploration_values, cmd};
  std::vector<std::string> incremental_sets{"plain", "furnished", "both"};
  TCLAP::ValuesConstraint<std::string> incremental_on_values{incremental_sets};
  TCLAP::ValueArg<std::string> incremental_on{"", "incremental-on",
                                              "Maps --incremental reveals (furnished and both "
                                              "need --furnished)",
                                              false, "plain", &incremental_on_values, cmd};
  TCLAP::ValueArg<double> range{"", "sensor-range", "Simulated laser range (m)", false, 5.0, "M",
                                cmd};
  TCLAP::ValueArg<double> spacing{"", "scan-spacing", "Travel between simulated scans (m)", false,
                                  0.5, "M", cmd};
};

/// The option values and combinations segment-eval refuses.
void checkSegmentEvalArgs(const SegmentEvalArgs& a) {
  if (!(a.res.getValue() > 0)) throw ConfigError("--resolution must be > 0");
  if (a.incremental_on.getValue() != "plain" && a.furnished.getValue().empty())
    throw ConfigError("--incremental-on " + a.incremental_on.getValue() + " needs --furnished");
  if (a.incremental_on.isSet() && !a.incremental.getValue())
    throw ConfigError("--incremental-on needs --incremental");
  if (a.exploration.isSet() && !a.incremental.getValue())
    throw ConfigError("--exploration needs --incremental");
}

/// The benchmark the options ask for.
studies::SegmentBenchmarkOptions benchmarkOptions(const SegmentEvalArgs& a) {
  studies::SegmentBenchmarkOptions o;
  o.plain_dir = a.plain.getValue();
  o.gt_dir = a.gt.getValue();
  o.furnished_dir = a.furnished.getValue();
  o.images_dir = a.images.getValue();
  o.reference_dir = a.reference.getValue();
  o.resolution = a.res.getValue();
  o.incremental = a.incremental.getValue();
  o.exploration = a.exploration.getValue();
  o.incremental_on = a.incremental_on.getValue();
  o.explore.sensor_range = a.range.getValue();
  o.explore.scan_spacing = a.spacing.getValue();
  return o;
}

}  // namespace

int cmdSegmentEval(int argc, char** argv) {
  TCLAP::CmdLine cmd(
      "Scores a segmenter on the room segmentation benchmark (Bormann et al., ICRA 2016) "
      "exactly as ../shared/docs/roomseg-eval.md describes: for every PLAIN/<name>.png, the "
      "ground truth GT/<name>_gt_segmentation.png (rooms: pixels > 250, 8-connected, more than "
      "100 px) and, with --furnished, FURNISHED/<name>_furnitures.png scored against the same "
      "rooms. Per map: precision (mean over segments of > 100 px of the best overlap / segment "
      "size), recall (mean over rooms of the best overlap / room size), their pooled variants "
      "(sum of best overlaps / sum of sizes), the Matthews correlation of 'same region' over "
      "pixel pairs (pixels in a counted room or segment; unlabelled ones are singletons), "
      "segment count and segment() time; then mean +- population std per variant. A fresh "
      "segmenter instance segments each map. --incremental also reveals every plain map (or "
      "those --incremental-on names) step by step and times the segmenter after every map "
      "update, passing it the previous segmentation: --exploration frontier, a simulated "
      "360-degree laser (perfect localization, nearest frontier first), or raster_disks, the "
      "thesis' own protocol (disks of 5 m revealed through walls every 2.5 m along rows, at "
      "0.05 m per pixel).",
      ' ', ASF_VERSION_STRING);
  SegmentEvalArgs args(cmd);
  cmd.setExceptionHandling(false);
  cmd.parse(argc, argv);
  checkSegmentEvalArgs(args);

  const SegmenterSetup setup =
      setupSegmenter(args.segmenter.getValue(), args.set.getValue(), args.path.getValue(), false);
  const studies::SegmentBenchmarkOptions o = benchmarkOptions(args);
  return scoreBenchmark(setup, o, args.only.getValue(), args.json_out.getValue());
}

}  // namespace asf::app
