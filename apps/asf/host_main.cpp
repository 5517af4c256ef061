// The host's commands behind one entry point, asf_host_main, which the `asf` launcher
// (launcher.cpp) loads on demand: this library pulls in MRPT, OpenCV, CGAL and the rest, about
// 300 libraries whose loading is most of a short command's time. Loads plugins through the
// registry and runs pipelines described by MRPT-style INI files.
#include <asf/abi.h>
#include <asf/errors.h>
#include <tclap/CmdLine.h>

#include <cstring>
#include <iomanip>
#include <iostream>
#include <new>

#include "commands.h"

namespace {

struct Command {
  const char* name;
  int (*fn)(int, char**);
  const char* summary;
};

const Command kCommands[] = {
    {"run", asf::app::cmdRun, "Run the pipeline of an INI file and write its outputs"},
    {"plugins", asf::app::cmdPlugins, "List the plugins found (name, kind, version, ABI, file)"},
    {"config", asf::app::cmdConfig, "Print an INI file resolved, every default filled in"},
    {"conformance", asf::app::cmdConformance,
     "Run the plugin conformance kit on plugin files or names"},
    {"route", asf::app::cmdRoute,
     "A route on a graph-list graph: euler, cpp, tsp, tarry, tarry_modified, tremaux, dfs"},
    {"optimize", asf::app::cmdOptimize,
     "Optimize a g2o pose graph with a back-end: chi2, iterations, time (--json)"},
    {"optimal", asf::app::cmdOptimal,
     "Certified optimal edge weights of a graph for D, A, E (optimum, gap, uniform efficiency)"},
    {"optimal-eval", asf::app::cmdOptimalEval,
     "D/A/E optima and route efficiencies (uniform, CPP, TSP, Tarry) over a graph list"},
    {"graph-gen", asf::app::cmdGraphGen,
     "Write a graph list of seeded grids, trees, small worlds or rooms-and-corridor graphs"},
    {"rawseeds2rawlog", asf::app::cmdRawseeds2Rawlog,
     "Convert Rawseeds CSV streams (.csv/.csv.bz2) to a rawlog + ground truth"},
    {"rawlog2rawseeds", asf::app::cmdRawlog2Rawseeds,
     "Write a rawlog as Rawseeds CSV streams (to test the converter)"},
    {"carmen2rawlog", asf::app::cmdCarmen2Rawlog,
     "Convert a CARMEN log to a rawlog + ground truth (optionally synthetic odometry)"},
    {"bag2rawlog", asf::app::cmdBag2Rawlog,
     "Convert a ROS 1 or ROS 2 bag (LaserScan, Odometry, /tf_static) to a rawlog"},
    {"rawlog-normalize", asf::app::cmdRawlogNormalize,
     "Rewrite a rawlog as timestamped action/sensory-frame pairs (for MRPT's tools)"},
    {"ate", asf::app::cmdAte,
     "Absolute trajectory error of a trajectory file vs ground truth (SE(2)-aligned)"},
    {"segment", asf::app::cmdSegment,
     "Segment one map image into regions: 16-bit label PNG, topological graph, overlay"},
    {"segment-eval", asf::app::cmdSegmentEval,
     "Score a segmenter on the room segmentation benchmark (precision, recall, MCC, time)"},
    {"segment-report", asf::app::cmdSegmentReport,
     "segment-eval reports side by side: thesis Table 4.1, Figs. 4.1 and 4.2 (MD, JSON, SVG)"},
    {"plan", asf::app::cmdPlan,
     "Most reliable path between two nodes of a g2o pose graph under a planner's criterion"},
    {"plan-eval", asf::app::cmdPlanEval,
     "Table 3.1 protocol: error rates of planners avoiding a feature-void zone of a SLAM graph"},
    {"recognition", asf::app::cmdRecognition,
     "Place recognition by Monte Carlo ICP on a SLAM run's nodes; Fig. 3.3 scatter (SVG)"},
    {"experiment", asf::app::cmdExperiment,
     "Replications x policies of an exploration pipeline in parallel: tables, plots, report"},
    {"map3d", asf::app::cmdMap3d,
     "3D observations of a rawlog into an OctoMap (.bt/.ot), projected to the 2D grid"},
    {"reproduce", asf::app::cmdReproduce,
     "The thesis' tables and figures of chapters 3-6 rerun: one report, thesis vs asf"},
};

void usage(std::ostream& os) {
  os << "asf " ASF_VERSION_STRING " (plugin ABI " << ASF_ABI_VERSION
     << "): Active SLAM framework\n\nUsage: asf <command> [options]   (asf <command> --help)\n\n"
        "Commands:\n";
  for (const auto& c : kCommands)
    os << "  " << std::left << std::setw(17) << c.name << c.summary << "\n";
  // Loaded by the launcher from its own module (apps/sim_robot), not one of this table's.
  os << "  " << std::left << std::setw(17) << "sim-robot"
     << "A simulated robot behind ROS 2 topics on Fast DDS (the optional ROS 2 component)\n";
  os << "\nPlugins are searched in <asf>/../lib/asf/plugins, $ASF_PLUGIN_PATH and the INI's "
        "[pipeline] plugin_path.\n";
}

}  // namespace

/// What `asf` does with its command line (argv[0] is the program).
extern "C" __attribute__((visibility("default"))) int asf_host_main(int argc, char** argv) {
  if (argc < 2) {
    usage(std::cerr);
    return asf::app::kUsage;
  }
  const std::string sub = argv[1];
  if (sub == "-h" || sub == "--help" || sub == "help") {
    usage(std::cout);
    return asf::app::kOk;
  }
  for (const auto& c : kCommands) {
    if (sub != c.name) continue;
    try {
      return c.fn(argc - 1, argv + 1);
    } catch (const TCLAP::ArgException& e) {
      std::cerr << "asf " << sub << ": " << e.argId() << ": " << e.error() << "\n"
                << "(asf " << sub << " --help)\n";
      return asf::app::kUsage;
    } catch (const TCLAP::ExitException& e) {
      return e.getExitStatus();
    } catch (const asf::Error& e) {
      std::cerr << "asf " << sub << ": error: " << e.what() << "\n";
      return asf::app::kError;
    } catch (const std::bad_alloc&) {
      std::cerr << "asf " << sub << ": error: out of memory (an input larger than this "
                << "machine can hold?)\n";
      return asf::app::kError;
    } catch (const std::exception& e) {
      std::cerr << "asf " << sub << ": unexpected error: " << e.what() << "\n";
      return asf::app::kError;
    }
  }
  std::cerr << "asf: unknown command '" << sub << "'\n\n";
  usage(std::cerr);
  return asf::app::kUsage;
}
