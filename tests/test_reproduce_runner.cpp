// The scheduler of `asf reproduce` (studies::reproduce::run) over the host's process launcher,
// with stages of shell commands instead of asf: commands in order with their outputs where
// they belong, failures and what they block, missing inputs, resume, the cores limit,
// commands that cannot start, and a stop request.
#include <asf/studies/reproduce.h>
#include <asf/text.h>
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <thread>

#include "process_launcher.h"
#include "test_util.h"

namespace fs = std::filesystem;
namespace rp = asf::studies::reproduce;

namespace {

rp::Command sh(const std::string& script, const std::string& stdout_file = "") {
  return {[script] { return std::vector<std::string>{"sh", "-c", script}; }, stdout_file};
}

rp::Settings settings(const std::string& name, int jobs) {
  rp::Settings s;
  s.out = asf_test::freshTempDir("asf_test_reproduce_runner_" + name).string();
  s.shared = "/data";
  s.jobs = jobs;
  return s;
}

struct Outcome {
  std::vector<rp::StageResult> results;
  std::vector<std::string> lines;
  std::string all() const {
    std::string a;
    for (const auto& l : lines) a += l + "\n";
    return a;
  }
};

Outcome runStages(const std::vector<rp::Stage>& stages, const rp::Settings& s,
                  const std::atomic<bool>& stop) {
  asf::app::ProcessLauncher launcher("/bin/false");  // no stage runs asf here
  Outcome o;
  o.results = rp::run(stages, s, launcher, stop, [&](const std::string& l) { o.lines.push_back(l); });
  return o;
}

std::string read(const std::string& path) { return asf_test::readFile(path); }

bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

}  // namespace

TEST(ReproduceRunner, CommandsInOrderFailuresBlockAndResumeKeepsDoneStages) {
  const rp::Settings s = settings("order", 2);
  const std::atomic<bool> stop{false};
  std::vector<rp::Stage> stages(5);
  stages[0].id = "a";
  // The second command's argv is built when it starts, after the first wrote its file.
  stages[0].commands = {sh("echo first; echo warn >&2", "first.txt"),
                        {[&s] {
                           return std::vector<std::string>{"sh", "-c",
                                                           "cat " + s.out + "/a/first.txt"};
                         },
                         ""}};
  stages[1].id = "b";
  stages[1].after = {"a"};
  stages[1].commands = {sh("echo broken >&2; exit 3")};
  stages[2].id = "c";
  stages[2].after = {"b"};
  stages[2].commands = {sh("true")};
  stages[3].id = "d";
  stages[3].inputs = {s.out + "/no_such_input"};
  stages[3].commands = {sh("true")};
  stages[4].id = "e";
  stages[4].commands = {{[]() -> std::vector<std::string> { return {"/no/such/program"}; }, ""}};
  Outcome o = runStages(stages, s, stop);

  EXPECT_EQ(o.results[0].status, rp::StageResult::kDone) << o.all();
  EXPECT_EQ(read(s.out + "/a/first.txt"), "first\n");  // stdout to its file
  const std::string log_a = read(s.out + "/a/stage.log");
  EXPECT_TRUE(has(log_a, "$ sh -c echo first; echo warn >&2 > first.txt\nwarn\n")) << log_a;
  EXPECT_TRUE(has(log_a, "/a/first.txt\nfirst\n")) << "the second command's stdout: " << log_a;
  EXPECT_TRUE(fs::exists(s.out + "/a/done.json"));

  EXPECT_EQ(o.results[1].status, rp::StageResult::kFailed);
  EXPECT_EQ(o.results[1].why, "exit code 3; see b/stage.log");
  EXPECT_TRUE(has(read(s.out + "/b/stage.log"), "broken\nexit code 3\n"));
  EXPECT_FALSE(fs::exists(s.out + "/b/done.json"));
  EXPECT_EQ(o.results[2].status, rp::StageResult::kSkipped);
  EXPECT_EQ(o.results[2].why, "needs stage b, which failed");
  EXPECT_EQ(o.results[3].status, rp::StageResult::kSkipped);
  EXPECT_EQ(o.results[3].why, "needs " + s.out + "/no_such_input, which does not exist");
  EXPECT_EQ(o.results[4].status, rp::StageResult::kFailed);
  EXPECT_TRUE(has(o.results[4].why, "/no/such/program: cannot start")) << o.results[4].why;
  EXPECT_TRUE(has(o.all(), "b FAILED after")) << o.all();

  // Again with b mended: a is kept, b and then c run.
  stages[1].commands = {sh("true")};
  o = runStages(stages, s, stop);
  EXPECT_EQ(o.results[0].status, rp::StageResult::kReused) << o.all();
  EXPECT_EQ(o.results[1].status, rp::StageResult::kDone);
  EXPECT_EQ(o.results[2].status, rp::StageResult::kDone);
  EXPECT_TRUE(has(o.all(), "1 of 5 stages done before with these settings")) << o.all();
}

TEST(ReproduceRunner, OneCoreRunsOneStageAtATime) {
  const rp::Settings s = settings("cores", 1);
  const std::atomic<bool> stop{false};
  const std::string trace = s.out + "/trace.txt";
  std::vector<rp::Stage> stages(3);
  for (int i = 0; i < 3; ++i) {
    const std::string id = std::string(1, static_cast<char>('x' + i));
    stages[i].id = id;
    stages[i].commands = {
        sh("echo start " + id + " >> " + trace + "; sleep 0.2; echo end " + id + " >> " + trace)};
  }
  const Outcome o = runStages(stages, s, stop);
  for (const auto& r : o.results) EXPECT_EQ(r.status, rp::StageResult::kDone) << o.all();
  EXPECT_EQ(read(trace), "start x\nend x\nstart y\nend y\nstart z\nend z\n");
}

TEST(ReproduceRunner, StopInterruptsTheRunningCommandsAndStartsNothing) {
  const rp::Settings s = settings("stop", 1);
  std::atomic<bool> stop{false};
  std::vector<rp::Stage> stages(2);
  stages[0].id = "long";
  stages[0].commands = {sh("sleep 30; echo finished > " + s.out + "/marker"), sh("echo never")};
  stages[1].id = "next";
  stages[1].commands = {sh("true")};
  std::thread stopper([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    stop = true;
  });
  const Outcome o = runStages(stages, s, stop);
  stopper.join();
  EXPECT_FALSE(fs::exists(s.out + "/marker")) << "SIGINT to its group ended the command";
  EXPECT_EQ(o.results[0].status, rp::StageResult::kNotRun) << o.all();
  EXPECT_EQ(o.results[0].why, "interrupted; see long/stage.log");
  EXPECT_FALSE(has(read(s.out + "/long/stage.log"), "echo never"));
  EXPECT_EQ(o.results[1].status, rp::StageResult::kNotRun);
  EXPECT_EQ(o.results[1].why, "interrupted before it started");
}

// Chapter 6 runs TIGRE as the thesis defines it: the experiments' INIs and the Fig. 6.1 run
// carry the same overrides, and configs/experiment_cave_as_thesis.ini (the command
// docs/benchmarks/exploration.md gives) the same again.
TEST(ReproducePlan, ChapterSixRunsTheThesisConfigurationEverywhere) {
  const auto split = [](const std::string& list) {
    const std::vector<std::string> items = asf::splitTrimmed(list, ';');
    return std::set<std::string>(items.begin(), items.end());
  };
  const std::set<std::string> want = split(rp::kThesisCaveOverrides);
  ASSERT_TRUE(want.count("tigre.relocate=false") && want.count("dude.change_rule=reference") &&
              want.count("dude.variant=thesis"));

  std::ifstream ini(std::string(ASF_TEST_SOURCE_DIR) + "/configs/experiment_cave_as_thesis.ini");
  std::string line, overrides;
  while (std::getline(ini, line))
    if (line.rfind("overrides", 0) == 0) overrides = line.substr(line.find('=') + 1);
  EXPECT_EQ(split(overrides), want) << overrides;

  rp::Settings s = settings("plan", 2);
  s.configs = std::string(ASF_TEST_SOURCE_DIR) + "/configs";
  s.replications = 2;
  int checked = 0;
  for (const rp::Stage& st : rp::plan(s)) {
    if (st.id == "ch6_tigre") {
      const std::vector<std::string> argv = st.commands.at(0).argv();  // writes the INI
      const std::string text = read(argv.at(2));
      std::set<std::string> got;
      for (const std::string& kv : split(text.substr(text.find("overrides = ") + 12)))
        if (kv.rfind("pipeline.", 0) != 0) got.insert(kv);
      EXPECT_EQ(got, want) << text;
      EXPECT_TRUE(has(st.settings, "tigre.relocate=false")) << "a rerun redoes older stages";
      ++checked;
    }
    if (st.id == "ch6_fig_6_1") {
      const std::vector<std::string> argv = st.commands.at(0).argv();
      std::set<std::string> got;
      for (std::size_t i = 0; i + 1 < argv.size(); ++i)
        if (argv[i] == "--set" && argv[i + 1].rfind("pipeline.", 0) != 0) got.insert(argv[i + 1]);
      EXPECT_EQ(got, want);
      ++checked;
    }
  }
  EXPECT_EQ(checked, 2);
}
