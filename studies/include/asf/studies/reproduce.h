#pragma once
/// \file reproduce.h
/// `asf reproduce`: the thesis' tables and figures of chapters 3-6 rerun by asf, one report.
/// The work is a list of stages (each one or more asf commands writing into its own folder,
/// plan()), run by run() through the host's ProcessRunner, resuming from the stages already
/// done (stageSettings, recordedSettings);
/// then every row (figure | thesis value | asf value | difference | note) is read back from
/// the stages' outputs (collect()) and written as report.md/.html/.json (write()).
#include <asf/studies/process_runner.h>

#include <atomic>
#include <cstddef>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace asf::studies::reproduce {

/// What the command line chose; `fingerprint()` names it all (for the report), each stage
/// records the part its results depend on (stageSettings).
struct Settings {
  bool quick = false;
  std::string out;              ///< output folder (absolute)
  std::string shared;           ///< the datasets' folder, ../shared (absolute)
  std::string configs;          ///< asf's configs/ folder (absolute)
  std::string asf;              ///< this executable
  int jobs = 2;                 ///< stages (and experiment runs) at the same time
  int pairs = 0;                ///< Table 3.1: start/goal pairs per zone
  int recognition_samples = 0;  ///< Table 3.1: Monte Carlo ICP samples per node
  int figure_samples = 0;       ///< Fig. 3.3: samples at each drawn node
  int replications = 0;         ///< chapter 6: seeds per policy
  double max_distance = 0;      ///< chapter 6: stop each run after this far [m] (0: none)
  std::string fingerprint() const;
};

/// Chapter 6's setup on top of configs/cave_thesis.ini: TIGRE as the thesis defines it (DuDe's
/// thesis variant with its author's incremental change rule and a full segmentation after
/// every loop closure; Tarry's rule with the loop-closing tie-break only, no relocation,
/// region centres) and the robot's radius for both goal-planning policies, as
/// `[experiment] overrides`. configs/experiment_cave_as_thesis.ini holds the same (tested).
extern const char* const kThesisCaveOverrides;

/// One command of a stage. `argv` is built when the command starts (it may read what an
/// earlier command of the stage wrote); argv[0] == "asf" runs this executable. Its standard
/// output goes to `stdout_file` (relative to the stage folder; empty: the stage log).
struct Command {
  std::function<std::vector<std::string>()> argv;
  std::string stdout_file;
};

struct Stage {
  std::string id;                   ///< also its folder under OUT
  std::string title;                ///< what it reproduces, for progress lines
  std::vector<std::string> after;   ///< stages that must be done first
  std::vector<std::string> inputs;  ///< files it needs; a missing one skips it (named)
  std::vector<Command> commands;
  int slots = 1;  ///< cores it keeps busy
  /// The settings its results depend on besides the data folder ("pairs=60 ..."): a stage
  /// done before under the same ones is kept, under others it is done again.
  std::string settings = "";
};

/// What a stage's done.json must record for it to be kept: the data folder and st.settings.
std::string stageSettings(const Settings& s, const Stage& st);

/// What OUT/<stage>/done.json recorded ("" when the stage has not finished there).
std::string recordedSettings(const Settings& s, const Stage& st);

/// What became of a stage.
struct StageResult {
  enum Status { kDone, kReused, kFailed, kSkipped, kNotRun } status = kNotRun;
  double seconds = 0;
  std::string why;  ///< for failed / skipped / not run
};

/// The stages of the reproduction under `s`.
std::vector<Stage> plan(const Settings& s);

using Progress = std::function<void(const std::string&)>;

/// Runs the stages not done yet, `s.jobs` cores at a time, in list order as their
/// prerequisites allow; a stage's commands run one after the other, argv[0] "asf" being the
/// host's binary, stdout to the command's stdout_file or the stage log and stderr to
/// OUT/<id>/stage.log. `progress` gets a line per started and settled stage and, each minute,
/// what runs. When `stop` becomes true (the host's Ctrl-C) the running commands are
/// interrupted, no stage starts and their results say "interrupted". Results are in the order
/// of `stages`.
std::vector<StageResult> run(const std::vector<Stage>& stages, const Settings& s,
                             ProcessRunner& runner, const std::atomic<bool>& stop,
                             const Progress& progress);

/// One line of the report.
struct Row {
  std::string section;     ///< "Table 3.1", "Fig. 6.2", ...
  std::string item;        ///< what is compared
  std::string thesis;      ///< the thesis' value, as the thesis states it
  std::string asf;         ///< asf's value ("" when its stage did not produce it)
  std::string difference;  ///< asf against the thesis
  std::string note;        ///< why they differ, what was measured, which stage
  std::string stage;       ///< the stage whose output gives the asf value
};

/// A figure of the report: a file inside OUT.
struct Figure {
  std::string section;
  std::string caption;
  std::string file;  ///< relative to OUT
};

struct Report {
  std::vector<Row> rows;
  /// Rows without an asf value.
  std::size_t missing() const;
  std::vector<Figure> figures;
  /// Per section, in order: what was run and why asf differs, said once for its rows.
  std::vector<std::pair<std::string, std::string>> sections;
};

/// Reads every row and figure from the stages' outputs in `s.out`; a row whose output is
/// missing keeps an empty asf value and a note naming the stage.
Report collect(const Settings& s, const std::vector<Stage>& stages,
               const std::vector<StageResult>& results);

/// Writes OUT/report.json, report.md and report.html (figures embedded).
void write(const Settings& s, const Report& r, const std::vector<Stage>& stages,
           const std::vector<StageResult>& results);

}  // namespace asf::studies::reproduce
