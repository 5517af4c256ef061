// asf experiment --backend slurm, the parts that need no cluster: the array script executed
// by bash as a Slurm task would be (with a stand-in for asf that records its arguments), the
// quoting, the parsers of sbatch's and squeue's output, resubmission and exit codes, and the
// submit-follow-report loop against Slurm's commands answered by the test. The whole backend
// against a real one-node cluster: tests/scripts/slurm_local.sh.
#include <asf/errors.h>
#include <asf/studies/experiment.h>
#include <asf/studies/experiment_slurm.h>
#include <gtest/gtest.h>

#include <atomic>
#include <filesystem>
#include <optional>
#include <sstream>

#include "process_launcher.h"
#include "test_util.h"

namespace fs = std::filesystem;

namespace {

fs::path tempDir(const std::string& name) {
  return asf_test::freshTempDir("asf_test_slurm_" + name);
}

void write(const fs::path& p, const std::string& text) { asf_test::writeFile(p, text); }

std::string read(const fs::path& p) { return asf_test::readFile(p.string()); }

asf::studies::ExperimentConfig config(const fs::path& dir) {
  asf::studies::ExperimentConfig cfg;
  cfg.pipeline_ini = (dir / "pipe line.ini").string();  // a space: quoting matters
  cfg.policies = {"tigre", "frontier"};
  cfg.replications = 2;
  cfg.first_seed = 3;
  cfg.out_dir = (dir / "out").string();
  cfg.overrides = {"sim2d.map_image=it's here.png", "pipeline.max_steps=50"};
  return cfg;
}

/// A stand-in for asf: writes its arguments, one per line, to $1's --out folder as args.txt
/// and exits with the status in the file `status` beside it (0 if none).
std::string fakeAsf(const fs::path& dir) {
  const fs::path exe = dir / "fake asf";
  write(exe,
        "#!/bin/bash\n"
        "out=''; prev=''\n"
        "for a in \"$@\"; do [[ $prev == --out ]] && out=$a; prev=$a; done\n"
        "printf '%s\\n' \"$@\" > \"$out/args.txt\"\n"
        "echo 'some output'\n"
        "exit \"$(cat \"$(dirname \"$0\")/status\" 2> /dev/null || echo 0)\"\n");
  fs::permissions(exe, fs::perms::owner_exec, fs::perm_options::add);
  return exe.string();
}

int runTask(const asf::studies::SlurmBatch& b, std::size_t task) {
  std::string out;
  return asf::app::runCommand(
      {"env", "SLURM_ARRAY_TASK_ID=" + std::to_string(task), "bash", b.script}, out);
}

TEST(ExperimentSlurm, ArrayTasksRunTheLocalBackendsCommandLines) {
  const fs::path dir = tempDir("tasks");
  const asf::studies::ExperimentConfig cfg = config(dir);
  const std::string exe = fakeAsf(dir);
  asf::studies::SlurmOptions o;
  o.partition = "short";
  o.time_limit = "00:10:00";
  o.max_parallel = 3;
  o.sbatch_args = {"--mem=2G"};
  const asf::studies::SlurmBatch b = asf::studies::writeSlurmBatch(cfg, o, exe);
  ASSERT_EQ(b.runs.size(), 4u);
  ASSERT_EQ(b.tasks.size(), 4u);
  const std::string script = read(b.script);
  for (const char* line : {"#SBATCH --array=0-3%3\n", "#SBATCH --partition=short\n",
                           "#SBATCH --time=00:10:00\n", "#SBATCH --mem=2G\n"})
    EXPECT_NE(script.find(line), std::string::npos) << line << "\n" << script;
  std::string out;
  ASSERT_EQ(asf::app::runCommand({"bash", "-n", b.script}, out), 0) << out;
  for (std::size_t task = 0; task < b.tasks.size(); ++task) {
    const asf::studies::ExperimentRun& run = b.runs[b.tasks[task]];
    ASSERT_EQ(runTask(b, task), 0);
    // Bash saw exactly the arguments the local backend passes (quotes, spaces included).
    std::string expected;
    for (const auto& a : asf::studies::runArguments(cfg, run)) expected += a + "\n";
    std::string got = read(fs::path(run.dir) / "args.txt");
    EXPECT_EQ(got, expected) << "task " << task;
    EXPECT_EQ(read(fs::path(run.dir) / "run.log"), "some output\n");
    EXPECT_EQ(read(fs::path(run.dir) / "exit_code"), "0\n");
    EXPECT_TRUE(fs::path(run.dir).is_absolute());
  }
  // Seeds outer, policies inner, as the local backend orders them.
  EXPECT_EQ(b.runs[b.tasks[1]].policy, "frontier");
  EXPECT_EQ(b.runs[b.tasks[2]].seed, 4);
  // A task id beyond the array is refused.
  EXPECT_EQ(runTask(b, 9), 2);
}

TEST(ExperimentSlurm, FinishedRunsAreNotResubmittedAndExitCodesAreCollected) {
  const fs::path dir = tempDir("resume");
  asf::studies::ExperimentConfig cfg = config(dir);
  const std::string exe = fakeAsf(dir);
  // tigre seed 3 finished in an earlier invocation; frontier seed 3 was interrupted.
  write(dir / "out/tigre/seed_3/summary.json", R"({"stop_reason": "policy done: all"})");
  write(dir / "out/frontier/seed_3/summary.json", R"({"stop_reason": "interrupted"})");
  write(dir / "out/frontier/seed_3/exit_code", "130\n");
  asf::studies::SlurmBatch b = asf::studies::writeSlurmBatch(cfg, {}, exe);
  ASSERT_EQ(b.tasks.size(), 3u);
  EXPECT_TRUE(b.runs[0].skipped);
  EXPECT_FALSE(fs::exists(dir / "out/frontier/seed_3/exit_code")) << "stale exit status kept";
  EXPECT_NE(read(b.script).find("#SBATCH --array=0-2\n"), std::string::npos)
      << "three tasks, no limit asked for";
  EXPECT_EQ(asf::studies::slurmTasksEnded(b), 0u);
  write(dir / "status", "3");
  EXPECT_EQ(runTask(b, 0), 3);
  EXPECT_FALSE(fs::exists(dir / "out/frontier/seed_3/summary.json")) << "stale summary kept";
  EXPECT_EQ(asf::studies::slurmTasksEnded(b), 1u);
  const auto runs = asf::studies::collectSlurmBatch(b);
  EXPECT_EQ(runs[b.tasks[0]].exit_code, 3);
  EXPECT_EQ(runs[b.tasks[1]].exit_code, -1) << "a task that never ran has no status";

  // Everything finished: nothing to submit, no script.
  for (const char* r : {"frontier/seed_3", "tigre/seed_4", "frontier/seed_4"})
    write(dir / "out" / r / "summary.json", R"({"stop_reason": "max_steps"})");
  b = asf::studies::writeSlurmBatch(cfg, {}, exe);
  EXPECT_TRUE(b.tasks.empty());
  EXPECT_TRUE(b.script.empty());
}

TEST(ExperimentSlurm, QuotingSurvivesBash) {
  for (const std::string s : {"plain", "two words", "it's", "'", "$HOME", "a\"b", "`ls`",
                              "back\\slash", "", "new\nline", "*"}) {
    std::string out;
    ASSERT_EQ(asf::app::runCommand({"bash", "-c", "printf %s " + asf::studies::shellQuote(s)}, out), 0);
    EXPECT_EQ(out, s);
  }
}

TEST(ExperimentSlurm, SchedulerOutputsAndBadOptions) {
  EXPECT_EQ(asf::studies::parseSbatchJobId("4242\n"), "4242");
  EXPECT_EQ(asf::studies::parseSbatchJobId("77;cluster2\n"), "77");
  EXPECT_THROW(asf::studies::parseSbatchJobId("sbatch: error: Batch job submission failed\n"), asf::Error);
  const asf::studies::SlurmQueue q = asf::studies::parseSqueue("PENDING\nRUNNING\nRUNNING\nCOMPLETING\nFAILED\n");
  EXPECT_EQ(q.pending, 1);
  EXPECT_EQ(q.running, 3);
  EXPECT_EQ(q.other, 1);
  EXPECT_EQ(asf::studies::parseSqueue("").total(), 0);
  const auto states = asf::studies::parseSacctStates(
      "12_0|COMPLETED\n12_1|TIMEOUT\n12_2|CANCELLED by 0\n13_0|FAILED\n12|PENDING\n"
      "12_x|FAILED\n",
      "12");
  ASSERT_EQ(states.size(), 3u);
  EXPECT_EQ(states.at(0), "COMPLETED");
  EXPECT_EQ(states.at(1), "TIMEOUT");
  EXPECT_EQ(states.at(2), "CANCELLED");

  const fs::path dir = tempDir("bad");
  const asf::studies::ExperimentConfig cfg = config(dir);
  asf::studies::SlurmOptions o;
  o.partition = "two words";
  EXPECT_THROW(asf::studies::writeSlurmBatch(cfg, o, "/bin/true"), asf::ConfigError);
  o = {};
  o.max_parallel = -1;
  EXPECT_THROW(asf::studies::writeSlurmBatch(cfg, o, "/bin/true"), asf::ConfigError);
  o = {};
  o.sbatch_args = {"mem=2G"};
  EXPECT_THROW(asf::studies::writeSlurmBatch(cfg, o, "/bin/true"), asf::ConfigError);
}

// Issue 51: a line break in the output folder or in the experiment's INI path must not become
// a line of the array script (it would run on the cluster), nor end the #SBATCH directives
// early (sbatch stops reading them at the first line that is not a comment).
TEST(ExperimentSlurm, NoLineOfTheScriptComesFromAPath) {
  const fs::path dir = tempDir("inject");
  asf::studies::ExperimentConfig cfg = config(dir);
  cfg.out_dir = (dir / "out\ntouch X\n#").string();
  try {
    asf::studies::writeSlurmBatch(cfg, {}, "/bin/true");
    ADD_FAILURE() << "an output folder with a line break was accepted";
  } catch (const asf::ConfigError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("--out"), std::string::npos) << m;
    EXPECT_NE(m.find("out\\ntouch X\\n#"), std::string::npos) << m;  // shown, not broken
  }
  EXPECT_FALSE(fs::exists(dir / "out\ntouch X\n#")) << "nothing written";
  cfg.out_dir = (dir / "two words").string();
  EXPECT_THROW(asf::studies::writeSlurmBatch(cfg, {}, "/bin/true"), asf::ConfigError);

  // The INI in a folder whose name has line breaks: in the comment it is escaped, in the
  // task's command line it is one quoted argument; every #SBATCH line comes before it, and
  // the task run by bash does not run the line.
  const fs::path injected = dir / "INJECTED";
  const fs::path odd = dir / ("e\ntouch '" + injected.string() + "'\n#");
  fs::create_directories(odd);
  cfg = config(dir);
  cfg.pipeline_ini = (odd / "pipe.ini").string();
  const asf::studies::SlurmBatch b = asf::studies::writeSlurmBatch(cfg, {}, fakeAsf(dir));
  const std::string script = read(b.script);
  std::istringstream lines(script);
  std::string line;
  bool directives = true;
  for (int n = 1; std::getline(lines, line); ++n) {
    if (n == 1) continue;  // #!/bin/bash
    if (line.rfind("#SBATCH", 0) == 0)
      EXPECT_TRUE(directives) << "an #SBATCH line after other lines: " << line << "\n" << script;
    else
      directives = false;
  }
  EXPECT_NE(script.find("runs of " + dir.string() + "/e\\ntouch '"), std::string::npos) << script;
  ASSERT_EQ(runTask(b, 0), 0);
  EXPECT_FALSE(fs::exists(injected)) << script;
  const asf::studies::ExperimentRun& run = b.runs[b.tasks[0]];
  std::string expected;
  for (const auto& arg : asf::studies::runArguments(cfg, run)) expected += arg + "\n";
  EXPECT_EQ(read(fs::path(run.dir) / "args.txt"), expected);
}

// The job name is a label: a folder name's symbols become '_' (one per byte: α is two).
TEST(ExperimentSlurm, TheJobNameIsOneWord) {
  const fs::path dir = tempDir("jobname");
  asf::studies::ExperimentConfig cfg = config(dir);
  cfg.out_dir = (dir / "cave(α)").string();
  const asf::studies::SlurmBatch b = asf::studies::writeSlurmBatch(cfg, {}, "/bin/true");
  EXPECT_NE(read(b.script).find("#SBATCH --job-name=asf-cave____\n"), std::string::npos) << read(b.script);
}

}  // namespace

namespace {

/// Slurm's commands answered by the test through the ProcessRunner the backend uses: sbatch
/// prints a job id, the first squeue runs task 0's script for real (bash) and reports two tasks
/// queued, the second an empty queue; sacct knows tasks 1 and 2. Records every command.
class FakeSlurm : public asf::studies::ProcessRunner {
 public:
  std::vector<std::vector<std::string>> commands;
  std::string script;
  int squeues = 0;

  int run(const std::vector<std::string>& argv, std::string& output) override {
    commands.push_back(argv);
    output.clear();
    if (argv.at(0) == "sbatch") {
      script = argv.back();
      output = "4242;cluster\n";
    } else if (argv.at(0) == "squeue" && squeues++ == 0) {
      std::string ignored;
      asf::app::runCommand({"env", "SLURM_ARRAY_TASK_ID=0", "bash", script}, ignored);
      output = "RUNNING\nPENDING\n";
    } else if (argv.at(0) == "sacct") {
      output = "4242_1|TIMEOUT\n4242_2|CANCELLED by 0\n";
    }
    return 0;
  }
  long start(const std::vector<std::string>&, const Redirect&, std::string& error) override {
    error = "the Slurm backend starts no process itself";
    return -1;
  }
  std::optional<Exit> poll(long) override { return std::nullopt; }
  void interrupt(long) override {}
  void kill(long) override {}
};

/// A stand-in for asf run that finishes: a summary.json in its --out folder.
std::string finishingAsf(const fs::path& dir) {
  const fs::path exe = dir / "finishing asf";
  write(exe,
        "#!/bin/bash\n"
        "out=''; prev=''\n"
        "for a in \"$@\"; do [[ $prev == --out ]] && out=$a; prev=$a; done\n"
        "echo '{\"stop_reason\": \"policy done: test\"}' > \"$out/summary.json\"\n");
  fs::permissions(exe, fs::perms::owner_exec, fs::perm_options::add);
  return exe.string();
}

std::string joined(const std::vector<std::string>& lines) {
  std::string all;
  for (const auto& l : lines) all += l + "\n";
  return all;
}

}  // namespace

TEST(ExperimentSlurm, SubmitsFollowsAndNamesTheTasksThatDidNotFinish) {
  const fs::path dir = tempDir("follow");
  const asf::studies::ExperimentConfig cfg = config(dir);
  FakeSlurm slurm;
  std::vector<std::string> lines;
  const std::atomic<bool> stop{false};
  const int failed = asf::studies::runSlurmExperiment(
      cfg, {}, false, 0.01, finishingAsf(dir), slurm,
      [&](const std::string& l) { lines.push_back(l); }, stop);
  const std::string all = joined(lines);
  EXPECT_EQ(failed, 3) << all;  // task 0 ran and finished; 1-3 never ran
  EXPECT_NE(all.find("asf experiment: 4 runs, 0 finished earlier, 4 to submit"), std::string::npos)
      << all;
  EXPECT_NE(all.find("submitted as Slurm job 4242 (4 array tasks"), std::string::npos) << all;
  EXPECT_NE(all.find("slurm job 4242: 1/4 ended, 1 running, 1 pending"), std::string::npos) << all;
  EXPECT_NE(all.find("(task 1) did not finish (Slurm: TIMEOUT) (no exit status"),
            std::string::npos)
      << all;
  EXPECT_NE(all.find("(task 2) did not finish (Slurm: CANCELLED)"), std::string::npos) << all;
  EXPECT_EQ(all.find("(task 0) did not finish"), std::string::npos) << all;
  EXPECT_EQ(slurm.squeues, 2);
  std::vector<std::string> names;
  for (const auto& c : slurm.commands) names.push_back(c.at(0));
  EXPECT_EQ(names, (std::vector<std::string>{"sbatch", "squeue", "squeue", "sacct"}));
  EXPECT_EQ(slurm.commands[1], (std::vector<std::string>{"squeue", "-h", "-r", "-j", "4242", "-o",
                                                         "%T"}));
}

TEST(ExperimentSlurm, AStopCancelsTheJob) {
  const fs::path dir = tempDir("cancel");
  const asf::studies::ExperimentConfig cfg = config(dir);
  FakeSlurm slurm;
  std::vector<std::string> lines;
  const std::atomic<bool> stop{true};  // Ctrl-C came during the first poll
  asf::studies::runSlurmExperiment(cfg, {}, false, 0.01, finishingAsf(dir), slurm,
                                   [&](const std::string& l) { lines.push_back(l); }, stop);
  std::vector<std::string> names;
  for (const auto& c : slurm.commands) names.push_back(c.at(0));
  EXPECT_EQ(names, (std::vector<std::string>{"sbatch", "squeue", "scancel", "sacct"}));
  EXPECT_EQ(slurm.commands[2], (std::vector<std::string>{"scancel", "4242"}));
  EXPECT_NE(joined(lines).find("interrupted: scancel 4242"), std::string::npos) << joined(lines);
}
