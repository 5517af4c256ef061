#pragma once
// Subcommands of the asf host. Each parses its own arguments (TCLAP, with --help) and
// returns the process exit code; asf::Error escaping one is reported by main().
#include <string>
#include <vector>

namespace asf::app {

/// Exit codes shared by all subcommands.
enum Exit : int {
  kOk = 0,
  kError = 1,        ///< bad configuration, plugin or input
  kUsage = 2,        ///< bad command line
  kTestsFailed = 3,  ///< conformance tests failed
  kInterrupted = 130,  ///< SIGINT (Ctrl-C); SIGTERM gives 143: 128 + the signal, as shells do
};

/// The exit code of a command stopped by signal `signo` (SIGINT 130, SIGTERM 143).
inline int interruptedBy(int signo) { return 128 + signo; }

int cmdRun(int argc, char** argv);
int cmdPlugins(int argc, char** argv);
int cmdConfig(int argc, char** argv);
int cmdConformance(int argc, char** argv);
int cmdOptimize(int argc, char** argv);
int cmdOptimal(int argc, char** argv);
int cmdRoute(int argc, char** argv);
int cmdOptimalEval(int argc, char** argv);
int cmdGraphGen(int argc, char** argv);
int cmdRawseeds2Rawlog(int argc, char** argv);
int cmdRawlog2Rawseeds(int argc, char** argv);
int cmdCarmen2Rawlog(int argc, char** argv);
int cmdBag2Rawlog(int argc, char** argv);
int cmdRawlogNormalize(int argc, char** argv);
int cmdAte(int argc, char** argv);
int cmdSegment(int argc, char** argv);
int cmdSegmentEval(int argc, char** argv);
int cmdSegmentReport(int argc, char** argv);
int cmdPlan(int argc, char** argv);
int cmdPlanEval(int argc, char** argv);
int cmdRecognition(int argc, char** argv);
int cmdExperiment(int argc, char** argv);
int cmdMap3d(int argc, char** argv);
int cmdReproduce(int argc, char** argv);

}  // namespace asf::app
