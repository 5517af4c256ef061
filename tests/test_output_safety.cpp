// Output safety (issue 20, items 5-7). Output files (asf/atomic_file.h) go through a temporary
// file and a rename, except what must not be replaced: devices and pipes are written in
// place, a symbolic link keeps pointing where it did. Failures (a full disk) are errors and
// leave no temporary file behind; a run whose outputs cannot be written does not exit 0; a
// run stopped by SIGTERM writes its outputs and exits 143 (128 + the signal), not 130.
#include <asf/atomic_file.h>
#include <asf/errors.h>
#include <asf/pose_graph.h>
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>
#include <stdexcept>
#include <vector>

#include "test_util.h"

namespace {

namespace fs = std::filesystem;

fs::path tempDir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("asf_test_atomic_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::string readText(const fs::path& f) {
  std::ifstream in(f);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// A run's recordings: every one is closed even when one before fails, and the first loss is
// the error, after its label.
TEST(CloseEach, ClosesEveryFileAndReportsTheFirstLoss) {
  std::vector<int> closed;
  auto fail = [&](int k, const char* why) {
    return [&closed, k, why] {
      closed.push_back(k);
      throw std::runtime_error(why);
    };
  };
  try {
    asf::closeEach({{"a: ", [&] { closed.push_back(1); }},
               {"the bag b: ", fail(2, "metadata.yaml: write failed")},
               {"", fail(3, "c.rawlog: write failed")}});
    ADD_FAILURE() << "no error thrown";
  } catch (const asf::Error& e) {
    EXPECT_STREQ(e.what(), "the bag b: metadata.yaml: write failed");
  }
  EXPECT_EQ(closed, (std::vector<int>{1, 2, 3}));
  EXPECT_NO_THROW(asf::closeEach({{"a: ", [] {}}}));
}

TEST(AtomicFile, RegularFileIsReplacedWholeAndNoTemporaryStays) {
  const fs::path d = tempDir("regular");
  const std::string f = (d / "out.txt").string();
  asf::writeFileAtomically(f, "first\n");
  asf::writeFileAtomically(f, "second\n");
  EXPECT_EQ(readText(f), "second\n");
  EXPECT_FALSE(fs::exists(f + ".tmp"));
}

TEST(AtomicFile, SymbolicLinkStaysALinkToTheNewContent) {
  const fs::path d = tempDir("symlink");
  fs::create_directories(d / "real");
  asf::writeFileAtomically((d / "real" / "graph.g2o").string(), "old\n");
  fs::create_symlink(d / "real" / "graph.g2o", d / "link.g2o");
  asf::writeFileAtomically((d / "link.g2o").string(), "new\n");
  EXPECT_TRUE(fs::is_symlink(d / "link.g2o")) << "the link was replaced by a regular file";
  EXPECT_EQ(readText(d / "real" / "graph.g2o"), "new\n");
  EXPECT_FALSE(fs::exists(d / "real" / "graph.g2o.tmp"));
  EXPECT_FALSE(fs::exists(d / "link.g2o.tmp"));
}

// A FIFO (like `-o /dev/stdout` into a pipe) is written into, not replaced. The reader opens
// without blocking, so a broken implementation fails the test instead of hanging it.
TEST(AtomicFile, FifoIsWrittenInPlaceNotReplaced) {
  const fs::path d = tempDir("fifo");
  const std::string f = (d / "pipe").string();
  ASSERT_EQ(mkfifo(f.c_str(), 0600), 0);
  const int rd = open(f.c_str(), O_RDONLY | O_NONBLOCK);
  ASSERT_GE(rd, 0);
  asf::writeFileAtomically(f, "through the pipe\n");
  std::string got;
  char buf[256];
  for (ssize_t n; (n = read(rd, buf, sizeof buf)) > 0;)
    got.append(buf, static_cast<std::size_t>(n));
  close(rd);
  EXPECT_TRUE(fs::is_fifo(f)) << "the FIFO was replaced by a regular file";
  EXPECT_EQ(got, "through the pipe\n");
}

TEST(AtomicFile, FullDiskAndDirectoriesAreErrorsNamingTheFile) {
  if (fs::exists("/dev/full")) {  // every write: ENOSPC
    const std::string msg =
        asf_test::errorOf<asf::Error>([] { asf::writeFileAtomically("/dev/full", "x", "graph"); });
    EXPECT_TRUE(asf_test::has(msg, "/dev/full: cannot write the graph")) << msg;
    EXPECT_TRUE(fs::is_character_file("/dev/full"));
  }
  const fs::path d = tempDir("dir");
  const std::string msg =
      asf_test::errorOf<asf::Error>([&] { asf::writeFileAtomically(d.string(), "x", "plot"); });
  EXPECT_TRUE(asf_test::has(msg, "is a directory")) << msg;
}

TEST(AtomicFile, AFailedWriterLeavesNoTemporaryAndKeepsTheOldFile) {
  const fs::path d = tempDir("failed");
  const std::string f = (d / "map.bt").string();
  asf::writeFileAtomically(f, "old\n");
  EXPECT_THROW(asf::writeFileVia(f, "3D map",
                                 [](const std::string& tmp) {
                                   std::ofstream(tmp) << "half a fi";
                                   return false;
                                 }),
               asf::Error);
  EXPECT_FALSE(fs::exists(f + ".tmp"));
  EXPECT_EQ(readText(f), "old\n");
  EXPECT_THROW(asf::writeFileVia(f, "3D map",
                                 [](const std::string& tmp) -> bool {
                                   std::ofstream(tmp) << "half";
                                   throw std::runtime_error("writer crashed");
                                 }),
               std::runtime_error);
  EXPECT_FALSE(fs::exists(f + ".tmp"));
}

TEST(AtomicFile, G2oThroughALinkAndIntoDevNull) {
  asf::PoseGraph g;
  g.addNode(mrpt::poses::CPose2D(), 0);
  g.addNode(mrpt::poses::CPose2D(1, 0, 0), 1);
  const fs::path d = tempDir("g2o");
  asf::writeG2o(g, (d / "a.g2o").string());
  fs::create_symlink(d / "a.g2o", d / "b.g2o");
  asf::writeG2o(g, (d / "b.g2o").string());
  EXPECT_TRUE(fs::is_symlink(d / "b.g2o"));
  EXPECT_EQ(asf::readG2o((d / "b.g2o").string()).size(), 2u);
  if (fs::exists("/dev/null")) {
    asf::writeG2o(g, "/dev/null");
    EXPECT_TRUE(fs::is_character_file("/dev/null")) << "/dev/null was replaced";
  }
}

// A run whose outputs cannot be written (graph.g2o is a directory here) says so and exits 1
// instead of 0, and names the file; the other outputs are still written.
TEST(RunExit, OutputsThatCannotBeWrittenAreANonZeroExit) {
  const fs::path d = tempDir("run");
  fs::create_directories(d / "out" / "graph.g2o");
  const auto r = asf_test::runHost(std::string("run ") + ASF_TEST_SOURCE_DIR +
                                   "/configs/two_rooms_scripted.ini --out " + (d / "out").string());
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_TRUE(asf_test::has(r.out, "outputs not written")) << r.out;
  EXPECT_TRUE(asf_test::has(r.out, "graph.g2o")) << r.out;
  EXPECT_TRUE(fs::exists(d / "out" / "summary.json"));
  EXPECT_TRUE(fs::exists(d / "out" / "keyframes.txt"));
}

// SIGTERM (what `kill`, systemd and Slurm send) stops a run like Ctrl-C does, outputs
// written, but the exit code says which signal it was.
TEST(RunExit, SigtermWritesTheOutputsAndExits143) {
  const fs::path d = tempDir("sigterm");
  std::string route;  // back and forth for long enough to be stopped midway
  for (int i = 0; i < 400; ++i) route += i % 2 ? "0 0; " : "2.5 0.5; ";
  route += "0 0";
  const std::string log = (d / "run.log").string();
  const pid_t pid =
      asf_test::spawnHost({"run", ASF_TEST_SOURCE_DIR "/configs/two_rooms_scripted.ini", "--out",
                           (d / "out").string(), "--set", "waypoints.waypoints=" + route},
                          log);
  ASSERT_GT(pid, 0);
  // Steps written: the run is past installing its handlers.
  const auto t0 = std::chrono::steady_clock::now();
  std::error_code ec;
  auto started = [&] {
    const auto size = fs::file_size(d / "out" / "trajectory.csv", ec);
    return !ec && size >= 2000;
  };
  while (!started() && std::chrono::steady_clock::now() - t0 < std::chrono::seconds(60))
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  ASSERT_TRUE(started()) << readText(log);
  kill(pid, SIGTERM);
  int st = 0;
  ASSERT_EQ(waitpid(pid, &st, 0), pid);
  const std::string out = readText(log);
  ASSERT_TRUE(WIFEXITED(st)) << out;
  EXPECT_EQ(WEXITSTATUS(st), 143) << out;
  EXPECT_TRUE(fs::exists(d / "out" / "summary.json")) << out;
  EXPECT_TRUE(fs::exists(d / "out" / "graph.g2o")) << out;
}

// Two runs into one folder would interleave their files: the second stops before writing
// anything, naming the folder and the first run's process; once that one has ended (here by
// SIGTERM), the folder takes a new run.
TEST(RunExit, ASecondRunIntoTheSameFolderIsRefusedWhileTheFirstRuns) {
  const fs::path d = tempDir("lock");
  std::string route;
  for (int i = 0; i < 400; ++i) route += i % 2 ? "0 0; " : "2.5 0.5; ";
  route += "0 0";
  const std::string config = ASF_TEST_SOURCE_DIR "/configs/two_rooms_scripted.ini";
  const std::string out = (d / "out").string();
  const pid_t pid = asf_test::spawnHost(
      {"run", config, "--out", out, "--set", "waypoints.waypoints=" + route},
      (d / "first.log").string());
  ASSERT_GT(pid, 0);
  const auto t0 = std::chrono::steady_clock::now();
  std::error_code ec;
  auto started = [&] { return fs::file_size(d / "out" / "trajectory.csv", ec) >= 2000 && !ec; };
  while (!started() && std::chrono::steady_clock::now() - t0 < std::chrono::seconds(60))
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  ASSERT_TRUE(started()) << readText(d / "first.log");
  const std::string log_before = readText(d / "out" / "run.log");
  const auto second = asf_test::runHost("run " + config + " --out " + out);
  EXPECT_EQ(second.code, 1) << second.out;
  EXPECT_TRUE(asf_test::has(second.out, out + ": another asf run is writing into this output "
                                              "folder (process " + std::to_string(pid) + ")"))
      << second.out;
  // Nothing of the second run in the first one's log (it only grew).
  EXPECT_EQ(readText(d / "out" / "run.log").compare(0, log_before.size(), log_before), 0);
  kill(pid, SIGTERM);
  int st = 0;
  ASSERT_EQ(waitpid(pid, &st, 0), pid);
  EXPECT_TRUE(WIFEXITED(st) && WEXITSTATUS(st) == 143) << readText(d / "first.log");
  EXPECT_TRUE(fs::exists(d / "out" / "summary.json"));
  const auto third = asf_test::runHost("run " + config + " --out " + out);
  EXPECT_EQ(third.code, 0) << third.out;
}

// Issue 23: SIGUSR1 pauses a run between two steps (progress.json says "paused", no step is
// written meanwhile) and a second SIGUSR1 resumes it; the run then ends exactly as one that
// was never paused.
TEST(RunExit, SigusrPausesAndResumesARunThatEndsAsIfNeverPaused) {
  const fs::path d = tempDir("pause");
  std::string route;
  for (int i = 0; i < 40; ++i) route += i % 2 ? "0 0; " : "2.5 0.5; ";
  route += "0 0";
  // 2522 steps; the sparse back-end keeps them to about a second (the INI's dense one: 2 min).
  const std::vector<std::string> args = {
      "run",   ASF_TEST_SOURCE_DIR "/configs/two_rooms_scripted.ini",
      "--set", "waypoints.waypoints=" + route,
      "--set", "pipeline.backend=sparse_lm"};
  std::vector<std::string> paused = args;
  paused.insert(paused.end(), {"--out", (d / "paused").string()});
  const std::string log = (d / "paused.log").string();
  const pid_t pid = asf_test::spawnHost(paused, log);
  ASSERT_GT(pid, 0);
  std::error_code ec;
  const fs::path traj = d / "paused" / "trajectory.csv";
  auto waitFor = [&](auto&& cond) {  // synchronisation only: generous, not a speed limit
    const auto t0 = std::chrono::steady_clock::now();
    while (!cond() && std::chrono::steady_clock::now() - t0 < std::chrono::seconds(60))
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    return cond();
  };
  ASSERT_TRUE(waitFor([&] { return fs::file_size(traj, ec) >= 2000 && !ec; })) << readText(log);
  kill(pid, SIGUSR1);
  auto status = [&] {
    try {
      return nlohmann::json::parse(readText(d / "paused" / "progress.json"))["status"]
          .get<std::string>();
    } catch (const std::exception&) {
      return std::string();
    }
  };
  ASSERT_TRUE(waitFor([&] { return status() == "paused"; })) << readText(log);
  const auto size = fs::file_size(traj);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  EXPECT_EQ(fs::file_size(traj), size) << "steps written while paused";
  kill(pid, SIGUSR1);
  int st = 0;
  ASSERT_EQ(waitpid(pid, &st, 0), pid);
  const std::string out = readText(log);
  ASSERT_TRUE(WIFEXITED(st)) << out;
  EXPECT_EQ(WEXITSTATUS(st), 0) << out;
  const std::string run_log = readText(d / "paused" / "run.log");
  EXPECT_TRUE(asf_test::has(run_log, "paused at step")) << run_log;
  EXPECT_TRUE(asf_test::has(run_log, "resumed at step")) << run_log;
  EXPECT_EQ(status(), "finished");
  // The same run without a pause: the same keyframes and trajectory to the digit.
  const std::string plain = "run " + args[1] + " --set \"" + args[3] + "\" --set " + args[5] +
                            " --out " + (d / "plain").string();
  const auto r = asf_test::runHost(plain);
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_EQ(readText(d / "paused" / "keyframes.txt"), readText(d / "plain" / "keyframes.txt"));
  EXPECT_EQ(readText(d / "paused" / "trajectory.csv"), readText(d / "plain" / "trajectory.csv"));
}

// Issue 20, item 8: after kill -9 every file already written is readable: the CSVs' rows
// whole, progress.json a valid summary of what was done ("running", steps and distance).
// SIGUSR2 sends the robot back to its start (the first keyframe) and ends the run there,
// with every output: an operator's "return home" (asf run's help; docs/ROS2.md).
TEST(RunExit, Sigusr2DrivesTheRobotHomeAndEndsTheRunThere) {
  const fs::path d = tempDir("home");
  std::string route;
  for (int i = 0; i < 40; ++i) route += i % 2 ? "0 0; " : "2.5 0.5; ";
  route += "0 0";
  const std::string log = (d / "home.log").string();
  const pid_t pid = asf_test::spawnHost({"run", ASF_TEST_SOURCE_DIR "/configs/two_rooms_scripted.ini",
                                         "--set", "waypoints.waypoints=" + route, "--set",
                                         "pipeline.backend=sparse_lm", "--out", (d / "run").string()},
                                        log);
  ASSERT_GT(pid, 0);
  std::error_code ec;
  const fs::path traj = d / "run" / "trajectory.csv";
  const auto t0 = std::chrono::steady_clock::now();  // synchronisation only, not a speed limit
  while (!(fs::file_size(traj, ec) >= 20000 && !ec) &&
         std::chrono::steady_clock::now() - t0 < std::chrono::seconds(60))
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  kill(pid, SIGUSR2);
  int st = 0;
  ASSERT_EQ(waitpid(pid, &st, 0), pid);
  const std::string out = readText(log);
  ASSERT_TRUE(WIFEXITED(st)) << out;
  EXPECT_EQ(WEXITSTATUS(st), 0) << out;
  const auto j = nlohmann::json::parse(readText(d / "run" / "summary.json"));
  const std::string why = j["stop_reason"];
  EXPECT_EQ(why.rfind("the operator asked to return home (SIGUSR2); back at the start (", 0), 0u) << why;
  EXPECT_FALSE(j["finished"].get<bool>());
  // Ended within the goal tolerance (0.3 m) of the start, plus the estimate's error.
  std::ifstream csv(traj);
  std::string header, line, first, last;
  std::getline(csv, header);
  std::getline(csv, first);
  for (last = first; std::getline(csv, line);) last = line;
  auto truth = [](const std::string& row) {
    std::vector<double> v;
    std::stringstream ss(row);
    for (std::string c; std::getline(ss, c, ',');) v.push_back(std::stod(c));
    return std::make_pair(v.at(5), v.at(6));  // gt_x, gt_y
  };
  const auto [x0, y0] = truth(first);
  const auto [x1, y1] = truth(last);
  EXPECT_LT(std::hypot(x1 - x0, y1 - y0), 0.5) << last;
  EXPECT_GT(j["steps"].get<int>(), 100);
}

TEST(RunExit, AfterSigkillTheFilesWrittenAreReadable) {
  const fs::path d = tempDir("sigkill");
  std::string route;
  for (int i = 0; i < 400; ++i) route += i % 2 ? "0 0; " : "2.5 0.5; ";
  route += "0 0";
  const pid_t pid =
      asf_test::spawnHost({"run", ASF_TEST_SOURCE_DIR "/configs/two_rooms_scripted.ini", "--out",
                           (d / "out").string(), "--set", "waypoints.waypoints=" + route},
                          (d / "run.log").string());
  ASSERT_GT(pid, 0);
  const auto t0 = std::chrono::steady_clock::now();
  std::error_code ec;
  auto started = [&] {
    const auto size = fs::file_size(d / "out" / "trajectory.csv", ec);
    return !ec && size >= 4000 && fs::exists(d / "out" / "progress.json");
  };
  while (!started() && std::chrono::steady_clock::now() - t0 < std::chrono::seconds(60))
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  ASSERT_TRUE(started()) << readText(d / "run.log");
  kill(pid, SIGKILL);
  int st = 0;
  ASSERT_EQ(waitpid(pid, &st, 0), pid);
  ASSERT_TRUE(WIFSIGNALED(st));
  const auto progress = nlohmann::json::parse(readText(d / "out" / "progress.json"));
  EXPECT_EQ(progress["status"], "running");
  EXPECT_GT(progress["step"].get<long>(), 0);
  EXPECT_FALSE(fs::exists(d / "out" / "summary.json")) << "the run was killed before its end";
  for (const char* csv : {"trajectory.csv", "timeseries.csv", "decisions.csv"}) {
    std::istringstream in(readText(d / "out" / csv));
    std::string header, line;
    std::getline(in, header);
    const auto columns = std::count(header.begin(), header.end(), ',');
    std::size_t rows = 0;
    while (std::getline(in, line)) {
      ++rows;
      if (std::count(line.begin(), line.end(), ',') != columns)
        ADD_FAILURE() << csv << " row " << rows << " is not whole: " << line;
    }
    EXPECT_TRUE(in.eof()) << csv;
  }
}

}  // namespace
