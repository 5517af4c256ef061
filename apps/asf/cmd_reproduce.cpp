// asf reproduce: reruns the thesis' tables and figures of chapters 3-6 (Tables 3.1, 3.2,
// 4.1, 5.1, Theorem 5.2.1, Figs. 3.3, 4.1-4.2, 5.6-5.13, 6.1-6.4) and writes one report:
// figure | thesis value | asf value | difference | note.
#include <asf/abi.h>
#include <asf/errors.h>
#include <asf/studies/reproduce.h>
#include <tclap/CmdLine.h>

#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <thread>

#include "commands.h"
#include "process_launcher.h"

namespace asf::app {

namespace fs = std::filesystem;

namespace {

namespace rp = studies::reproduce;

std::atomic<bool> g_stop{false};
std::atomic<int> g_signal{0};

/// The stages' results: run now (Ctrl-C stops them), or with --report-only those done before.
std::vector<rp::StageResult> stageResults(const std::vector<rp::Stage>& stages,
                                          const rp::Settings& s, bool report_only) {
  std::vector<rp::StageResult> results(stages.size());
  if (report_only) {
    for (std::size_t i = 0; i < stages.size(); ++i)
      if (rp::recordedSettings(s, stages[i]) == rp::stageSettings(s, stages[i]))
        results[i].status = rp::StageResult::kReused;
    return results;
  }
  std::cerr << "reproduce: " << stages.size() << " stages into " << s.out << " ("
            << s.fingerprint() << ", " << s.jobs << " cores)\n";
  withStopSignals(g_stop, g_signal, [&] {
    ProcessLauncher launcher(s.asf);
    results = rp::run(stages, s, launcher, g_stop,
                      [](const std::string& line) { std::cerr << line << "\n"; });
    return 0;
  });
  return results;
}

/// configs/ of the source tree when run from it, else the installed share/asf/configs.
std::string defaultConfigs(const std::string& exe) {
  if (fs::exists("configs/cave_thesis.ini")) return fs::absolute("configs").string();
  return (fs::path(exe).parent_path().parent_path() / "share/asf/configs").string();
}

/// --shared, else $ASF_SHARED_DIR, else ../shared; canonical. InputError if it is no folder.
std::string sharedDir(const std::string& arg) {
  const char* env_shared = std::getenv("ASF_SHARED_DIR");
  const std::string shared_dir = !arg.empty()                ? arg
                                 : env_shared && *env_shared ? env_shared
                                                             : "../shared";
  if (!fs::is_directory(shared_dir))
    throw InputError("--shared " + shared_dir +
                     ": no such folder (the datasets beside the repository: datasets/carmen, "
                     "roomseg, optexp, g2o)");
  return fs::canonical(shared_dir).string();
}

/// The reproduction's outcome on stdout; the exit code: interrupted (by the signal), kError
/// when a stage is not done or a row has no asf value, else kOk.
int reportOutcome(const rp::Report& report, std::size_t stages,
                  const std::vector<rp::StageResult>& results, const std::string& out) {
  const std::size_t missing = report.missing();
  std::size_t bad_stages = 0;
  bool interrupted = false;
  for (const auto& r : results) {
    bad_stages += r.status != rp::StageResult::kDone && r.status != rp::StageResult::kReused;
    interrupted = interrupted || r.why.find("interrupted") != std::string::npos;
  }
  std::cout << "reproduce: " << report.rows.size() << " rows (" << missing
            << " without an asf value), " << report.figures.size() << " figures; "
            << stages - bad_stages << "/" << stages << " stages done\nwrote " << out
            << "/report.md, report.html, report.json\n";
  if (interrupted) return g_signal ? interruptedBy(g_signal) : kInterrupted;
  return missing == 0 && bad_stages == 0 ? kOk : kError;
}

}  // namespace

int cmdReproduce(int argc, char** argv) {
  TCLAP::CmdLine cmd(
      "Reruns the thesis' tables and figures of chapters 3-6 and writes one report (report.md, "
      "report.html with the figures embedded, report.json): per row the thesis value, asf's "
      "value, the difference and a note. Stages: graph SLAM on the intel and aces CARMEN logs "
      "and Table 3.1 on both with Figs. 3.4-3.5, Figs. 3.1-3.2 (the hypotheses merge against "
      "their enumeration) and Table 3.2 (aces partially explored), Fig. 3.3; Table 4.1 and Figs. "
      "4.1-4.4 (room segmentation benchmark); Table 5.1 (the thesis' 174 graphs), Theorem 5.2.1 "
      "(intel, MIT, a cave run), Figs. 5.5-5.10 (walks on K4 and a generic graph) and "
      "5.11-5.13; the cave with the author's robot, four policies (Figs. 6.2-6.4) and Figs. 6.1 "
      "and 4.5 (one TIGRE run). Data from --shared "
      "(../shared: datasets/carmen, roomseg, optexp, g2o); a stage whose data is missing is "
      "skipped and named. Each stage runs asf commands into OUT/<stage>/ (stage.log: their "
      "commands and messages); a stage done before with the same settings is kept, so an "
      "interrupted reproduction resumes. Full: about 40 min on 2 cores; --quick: smoke-run sizes "
      "in a few minutes. Exit code 0 when every stage ran and every row has a value.",
      ' ', ASF_VERSION_STRING);
  TCLAP::SwitchArg quick("", "quick", "Smoke-run sizes (every row, in a few minutes)", cmd);
  TCLAP::ValueArg<std::string> out("o", "out", "Output folder (default results/reproduce[-quick])",
                                   false, "", "DIR", cmd);
  TCLAP::ValueArg<std::string> shared(
      "", "shared", "The datasets' folder (default $ASF_SHARED_DIR, else ../shared)", false, "",
      "DIR", cmd);
  TCLAP::ValueArg<std::string> configs(
      "", "configs", "asf's configs folder (default ./configs, else the installed one)", false, "",
      "DIR", cmd);
  TCLAP::ValueArg<int> jobs("j", "jobs", "Cores to use (0: all)", false, 0, "N", cmd);
  TCLAP::ValueArg<int> pairs("", "pairs",
                             "Table 3.1: start/goal pairs per zone (default 60; --quick 4)", false,
                             0, "N", cmd);
  TCLAP::ValueArg<int> replications("", "replications",
                                    "Chapter 6: seeds per policy (default 10; --quick 1)", false, 0,
                                    "N", cmd);
  TCLAP::SwitchArg report_only("", "report-only",
                               "Run nothing: write the report from the stages done", cmd);
  cmd.parse(argc, argv);

  rp::Settings s;
  s.quick = quick.getValue();
  s.asf = asfExecutable();
  s.shared = sharedDir(shared.getValue());
  s.configs = configs.getValue().empty() ? defaultConfigs(s.asf) : configs.getValue();
  if (!fs::exists(fs::path(s.configs) / "cave_thesis.ini"))
    throw InputError("--configs " + s.configs +
                     ": no cave_thesis.ini there (asf's configs/ folder)");
  s.configs = fs::canonical(s.configs).string();
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  s.jobs = jobs.getValue() > 0 ? jobs.getValue() : static_cast<int>(cores);
  if (jobs.getValue() < 0) throw InputError("--jobs must be >= 0");
  s.pairs = pairs.getValue() > 0 ? pairs.getValue() : s.quick ? 4 : 60;
  s.recognition_samples = s.quick ? 5 : 40;
  s.figure_samples = s.quick ? 20 : 100;
  s.replications = replications.getValue() > 0 ? replications.getValue() : s.quick ? 1 : 10;
  s.max_distance = s.quick ? 40 : 0;
  const std::string out_dir = !out.getValue().empty() ? out.getValue()
                              : s.quick               ? "results/reproduce-quick"
                                                      : "results/reproduce";
  fs::create_directories(out_dir);
  s.out = fs::canonical(out_dir).string();

  const auto stages = rp::plan(s);
  const std::vector<rp::StageResult> results = stageResults(stages, s, report_only.getValue());
  const rp::Report report = rp::collect(s, stages, results);
  rp::write(s, report, stages, results);
  return reportOutcome(report, stages.size(), results, s.out);
}

}  // namespace asf::app
