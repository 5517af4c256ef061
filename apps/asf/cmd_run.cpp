#include <asf/errors.h>
#include <asf/evaluation/map_views.h>
#include <asf/framework/pipeline.h>
#include <dlfcn.h>
#include <tclap/CmdLine.h>

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <thread>

#include "commands.h"

namespace asf::app {

namespace {
std::atomic<bool> g_stop{false}, g_pause{false}, g_home{false};
std::atomic<int> g_signal{0};
extern "C" void onSignal(int signo) {
  g_signal = signo;
  g_stop = true;
}
extern "C" void onPauseSignal(int) { g_pause = !g_pause.load(); }
extern "C" void onHomeSignal(int) { g_home = true; }
/// The live view's window, from libasf_live_window.so beside this library (MRPT's GUI, wx and
/// GTK are loaded only for --gui).
class LiveWindow {
 public:
  explicit LiveWindow(const std::string& title) {
    if (!std::getenv("DISPLAY") || !*std::getenv("DISPLAY"))
      throw InputError("asf run --gui: no display (DISPLAY is not set); run without --gui");
    Dl_info info{};
    dladdr(reinterpret_cast<void*>(&cmdRun), &info);
    const std::string here = info.dli_fname ? info.dli_fname : "";
    const std::string lib = here.substr(0, here.find_last_of('/') + 1) + "libasf_live_window.so";
    handle_ = dlopen(lib.c_str(), RTLD_LAZY | RTLD_LOCAL);
    if (!handle_) throw Error(std::string("asf run --gui: ") + dlerror());
    open_ = sym<void* (*)(const char*)>("asf_live_window_open");
    show_ = sym<void (*)(void*, int, int, const unsigned char*)>("asf_live_window_show");
    is_open_ = sym<int (*)(void*)>("asf_live_window_is_open");
    close_ = sym<void (*)(void*)>("asf_live_window_close");
    window_ = open_(title.c_str());
  }
  ~LiveWindow() {
    if (window_) close_(window_);
  }
  void show(const evaluation::ViewImage& v) {
    if (is_open_(window_)) show_(window_, v.width, v.height, v.bgr.data());
  }
  /// After the run: `seconds` (< 0: until the window is closed or the run is interrupted).
  void hold(double seconds, const std::atomic<bool>& stop) {
    const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (is_open_(window_) && !stop && (seconds < 0 || std::chrono::steady_clock::now() < until))
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }

 private:
  template <class F>
  F sym(const char* name) {
    void* p = dlsym(handle_, name);
    if (!p) throw Error(std::string("asf run --gui: libasf_live_window.so has no ") + name);
    return reinterpret_cast<F>(p);
  }
  void* handle_ = nullptr;
  void* window_ = nullptr;
  void* (*open_)(const char*) = nullptr;
  void (*show_)(void*, int, int, const unsigned char*) = nullptr;
  int (*is_open_)(void*) = nullptr;
  void (*close_)(void*) = nullptr;
};

/// --resume RUN: the run's own config.ini unless one is given, RUN_resumed unless --out is.
void resumeSettings(const std::string& run, std::string& config_file, std::string& out) {
  namespace fs = std::filesystem;
  if (!fs::is_directory(run)) throw InputError("asf run --resume " + run + ": not a folder");
  if (config_file.empty()) config_file = (fs::path(run) / "config.ini").string();
  std::string base = fs::path(run).lexically_normal().string();
  while (base.size() > 1 && base.back() == '/') base.pop_back();
  if (out.empty()) out = base + "_resumed";
  if (fs::exists(out) && fs::equivalent(out, run))
    throw InputError("asf run --resume " + run +
                     ": --out is the run's own folder; the resumed run is written elsewhere "
                     "(the interrupted one stays as it is)");
}

/// CONFIG with the command line's keys over it: --resume's (the run to continue), the --set
/// overrides, then --verbosity.
IniConfig pipelineIni(const std::string& config_file, const std::string& resume,
                      const std::vector<std::string>& sets, const std::string& verbosity) {
  IniConfig ini = IniConfig::fromFile(config_file);
  if (!resume.empty()) {
    const std::string run = std::filesystem::absolute(resume).lexically_normal().string();
    ini.set("pipeline", "resume", run, "--resume");
    ini.set(ini.get("pipeline", "source"), "resume_from", run, "--resume");
  }
  for (const auto& s : sets) ini.applyOverride(s);
  if (!verbosity.empty()) ini.set("pipeline", "verbosity", verbosity, "--verbosity");
  return ini;
}

/// Runs the pipeline with Ctrl-C/SIGTERM (stop), SIGUSR1 (pause, resume) and SIGUSR2 (back to
/// the start) handled; the default handlers are back after.
framework::RunSummary runWithSignals(framework::Pipeline& pipeline) {
  std::signal(SIGINT, onSignal);
  std::signal(SIGTERM, onSignal);
  std::signal(SIGUSR1, onPauseSignal);
  std::signal(SIGUSR2, onHomeSignal);
  framework::RunSummary s = pipeline.run(&g_stop, &g_pause, &g_home);
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
  std::signal(SIGUSR1, SIG_DFL);
  std::signal(SIGUSR2, SIG_DFL);
  return s;
}

/// The run's outcome and where its files are, on stdout.
void printOutcome(const framework::RunSummary& s, const std::string& dir) {
  std::cout << "asf run: " << s.stop_reason << " after " << s.steps << " steps, " << s.distance_m
            << " m, " << s.nodes << " nodes, " << s.edges << " edges, " << s.regions << " regions";
  if (s.final_pose_error_m >= 0)
    std::cout << ", final pose error " << s.final_pose_error_m << " m (mean " << s.mean_pose_error_m
              << " m)";
  if (s.ate_rmse_m >= 0)
    std::cout << ", ATE RMSE " << s.ate_rmse_m << " m (max " << s.ate_max_m << " m, " << s.ate_poses
              << " keyframes)";
  if (s.coverage >= 0) std::cout << ", coverage " << 100 * s.coverage << "%";
  std::cout << " in " << s.wall_time_s << " s\n";
  std::cout << "asf run: results in " << std::filesystem::absolute(dir).lexically_normal().string()
            << "/ (";
  const auto files = framework::Pipeline::outputFiles();
  for (std::size_t i = 0; i < files.size(); ++i) std::cout << (i ? ", " : "") << files[i];
  std::cout << ")\n";
  const auto report = (std::filesystem::absolute(dir) / "report.html").lexically_normal();
  if (std::filesystem::exists(report)) std::cout << "asf run: report: " << report.string() << "\n";
}

}  // namespace

int cmdRun(int argc, char** argv) {
  TCLAP::CmdLine cmd(
      "Runs the pipeline of CONFIG: source -> front-end -> back-end -> map -> segmenter -> "
      "topological graph -> policy, until the source ends, the policy is done or a budget is "
      "spent. Ctrl-C stops the run and still writes its outputs; SIGUSR1 (kill -USR1 PID) pauses "
      "it and a second SIGUSR1 resumes it (a live robot is stopped meanwhile); SIGUSR2 sends "
      "the robot back to its start and ends the run there.",
      ' ', ASF_VERSION_STRING);
  TCLAP::UnlabeledValueArg<std::string> config(
      "config", "Pipeline INI file (with --resume: the run's own config.ini by default)", false, "",
      "CONFIG.ini", cmd);
  TCLAP::ValueArg<std::string> out(
      "o", "out", "Output folder (default: results/<config name>; with --resume: RUN_resumed)",
      false, "", "DIR", cmd);
  TCLAP::ValueArg<std::string> resume(
      "r", "resume",
      "Continue the interrupted run in RUN: its recorded log goes through SLAM, maps and "
      "segmentation again, the policy retakes its recorded decisions, then the exploration "
      "goes on; the whole run is written to --out (RUN is only read). Raise the budget that "
      "stopped it with --set (e.g. pipeline.max_steps)",
      false, "", "RUN", cmd);
  TCLAP::MultiArg<std::string> set("s", "set", "Override a key: section.key=value (repeatable)",
                                   false, "section.key=value", cmd);
  TCLAP::SwitchArg gui("g", "gui",
                       "Watch the run in a window (MRPT): the map, its regions, the topological "
                       "graph, the pose graph, the path, the robot and its goal",
                       cmd);
  TCLAP::ValueArg<double> gui_refresh(
      "", "gui-refresh", "Seconds between two pictures of the live view", false, 0.5, "S", cmd);
  TCLAP::ValueArg<double> gui_hold(
      "", "gui-hold", "Seconds the window stays open after the run (default: until it is closed)",
      false, -1, "S", cmd);
  std::vector<std::string> levels{"DEBUG", "INFO", "WARN", "ERROR"};
  TCLAP::ValuesConstraint<std::string> lv(levels);
  TCLAP::ValueArg<std::string> verb(
      "v", "verbosity",
      "Log level (overrides [pipeline] verbosity), on the console too. Without it (and without "
      "verbosity in the INI) the console shows warnings, errors and one progress line; every "
      "line goes to the output folder's run.log",
      false, "", &lv, cmd);
  cmd.setExceptionHandling(false);
  cmd.parse(argc, argv);

  std::string config_file = config.getValue();
  std::string dir = out.getValue();
  if (!resume.getValue().empty())
    resumeSettings(resume.getValue(), config_file, dir);
  else if (config_file.empty())
    throw InputError("asf run: a CONFIG.ini is required (or --resume RUN)");
  IniConfig ini = pipelineIni(config_file, resume.getValue(), set.getValue(), verb.getValue());
  framework::Registry reg;
  const framework::ResolvedConfig rc = framework::resolveConfig(ini, reg);

  if (dir.empty()) dir = "results/" + std::filesystem::path(config_file).stem().string();
  // The window first: without a display nothing is created, not even the output folder.
  std::unique_ptr<LiveWindow> window;
  if (gui.getValue()) {
    if (!(gui_refresh.getValue() > 0))
      throw InputError("asf run --gui-refresh " + std::to_string(gui_refresh.getValue()) +
                       ": must be > 0 seconds");
    window = std::make_unique<LiveWindow>("asf run " + config_file);
  }
  framework::Pipeline pipeline(rc, dir);
  if (window) {
    LiveWindow* w = window.get();
    pipeline.setLiveView([w](const evaluation::ViewImage& v) { w->show(v); },
                         gui_refresh.getValue(), 800);
  }

  const framework::RunSummary s = runWithSignals(pipeline);
  printOutcome(s, dir);
  if (window) window->hold(gui_hold.getValue(), g_stop);
  if (!s.output_errors.empty()) {
    std::cerr << "asf run: error: outputs not written: " << s.output_errors << "\n";
    return g_stop ? interruptedBy(g_signal) : kError;
  }
  return g_stop ? interruptedBy(g_signal) : kOk;
}

}  // namespace asf::app
