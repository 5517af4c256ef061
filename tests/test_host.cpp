// The asf host as a user meets it: subcommands, --help, exit codes, messages.
#include <asf/abi.h>
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "test_util.h"

using asf_test::has;
namespace fs = std::filesystem;

namespace {

using Result = asf_test::HostResult;
Result asf(const std::string& args) { return asf_test::runHost(args); }

fs::path writeIni(const std::string& name, const std::string& text) {
  const fs::path f = fs::temp_directory_path() / name;
  std::ofstream(f) << text;
  return f;
}

}  // namespace

TEST(Host, HelpAndUsage) {
  auto r = asf("--help");
  EXPECT_EQ(r.code, 0);
  for (const char* c : {"run", "plugins", "config", "conformance"}) EXPECT_TRUE(has(r.out, c)) << c;
  r = asf("");
  EXPECT_EQ(r.code, 2);
  r = asf("fly");
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(has(r.out, "unknown command 'fly'"));
  for (const char* c : {"run", "plugins", "config", "conformance"}) {
    r = asf(std::string(c) + " --help");
    EXPECT_EQ(r.code, 0) << c << ": " << r.out;
    EXPECT_TRUE(has(r.out, "USAGE")) << c;
  }
  r = asf("run --no-such-flag x.ini");
  EXPECT_EQ(r.code, 2) << r.out;
}

// The launcher answers --version without the commands' library, and says where it looked
// when that library is missing (a copied or half-installed binary).
TEST(Host, LauncherVersionAloneAndAMissingHostLibraryIsNamed) {
  auto r = asf("--version");
  EXPECT_EQ(r.code, 0);
  EXPECT_EQ(r.out,
            "asf " ASF_VERSION_STRING " (plugin ABI " + std::to_string(ASF_ABI_VERSION) + ")\n");
  const fs::path dir = fs::temp_directory_path() / "asf_launcher_alone" / "bin";
  fs::create_directories(dir);
  fs::copy_file(ASF_TEST_BINARY_DIR "/bin/asf", dir / "asf", fs::copy_options::overwrite_existing);
  const std::string exe = (dir / "asf").string();
  auto run = [](const std::string& cmd) { return asf_test::runCommand(cmd + " 2>&1"); };
  r = run(exe + " --version");
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_TRUE(has(r.out, "asf " ASF_VERSION_STRING)) << r.out;
  r = run(exe + " plugins");
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_TRUE(has(r.out, "cannot load the host library")) << r.out;
  EXPECT_TRUE(has(r.out, "lib/asf/libasf_host.so")) << r.out;
  fs::remove_all(dir.parent_path());
}

TEST(Host, PluginsListsEveryKindAsJson) {
  const auto r = asf("plugins --json");
  ASSERT_EQ(r.code, 0) << r.out;
  const auto j = nlohmann::json::parse(r.out);
  std::set<std::string> kinds;
  for (const auto& p : j) {
    kinds.insert(p["kind"].get<std::string>());
    EXPECT_EQ(p["abi"], ASF_ABI_VERSION);
    EXPECT_TRUE(fs::exists(p["file"].get<std::string>()));
    EXPECT_FALSE(p["description"].get<std::string>().empty());
  }
  EXPECT_EQ(kinds, (std::set<std::string>{"source", "frontend", "backend", "segmenter", "planner",
                                          "policy"}));
}

TEST(Host, PluginsReportsBrokenFilesWithExitCode1) {
  const auto r = asf("plugins --plugin-path " ASF_TEST_BINARY_DIR "/tests/plugins/wrong_abi");
  EXPECT_EQ(r.code, 1);
  EXPECT_TRUE(has(r.out, "wrong_abi_policy.so: ABI mismatch")) << r.out;
}

TEST(Host, ConfigPrintsDefaultsAndRejectsTypos) {
  auto r =
      asf("config " ASF_TEST_SOURCE_DIR "/configs/two_rooms_scripted.ini --set map.resolution=0.1");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_TRUE(has(r.out, "resolution = 0.1"));
  EXPECT_TRUE(has(r.out, "[dense_gn]")) << "sections of selected plugins appear with defaults";
  const auto f = writeIni("asf_host_typo.ini",
                          "[pipeline]\nsource = segment_world\nfrontend = odometry\n"
                          "[segment_world]\nlaser_max_rnge = 3\n");
  r = asf("config " + f.string());
  EXPECT_EQ(r.code, 1);
  EXPECT_TRUE(has(r.out, f.string() + ":5: [segment_world] unknown key 'laser_max_rnge' (did you "
                                      "mean 'laser_max_range'?)"))
      << r.out;
  r = asf("config " + f.string() + " --set bogus");
  EXPECT_EQ(r.code, 1);
  EXPECT_TRUE(has(r.out, "expected section.key=value")) << r.out;
  fs::remove(f);
}

TEST(Host, RunWritesResultsAndSaysWhere) {
  const fs::path out = fs::temp_directory_path() / "asf_host_run";
  fs::remove_all(out);
  const auto r = asf("run " ASF_TEST_SOURCE_DIR "/configs/two_rooms_scripted.ini --out " +
                     out.string() + " --set pipeline.max_steps=50 -v WARN");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_TRUE(has(r.out, "step budget (50) spent")) << r.out;
  EXPECT_TRUE(has(r.out, "results in " + out.string())) << r.out;
  EXPECT_TRUE(fs::exists(out / "summary.json"));
  fs::remove_all(out);
}

// The console gets warnings, errors and the progress line; run.log in the output folder gets
// every line at the run's verbosity; -v puts that level on the console too.
TEST(Host, RunLogKeepsEveryLineAndTheConsoleTheProgress) {
  const fs::path out = fs::temp_directory_path() / "asf_host_run_log";
  fs::remove_all(out);
  const std::string run = "run " ASF_TEST_SOURCE_DIR "/configs/two_rooms_scripted.ini --out " +
                          out.string() + " --set pipeline.max_steps=50";
  auto r = asf(run);
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_FALSE(has(r.out, "|INFO |")) << r.out;
  EXPECT_TRUE(has(r.out, "\nstep 50 ") || r.out.rfind("step 50 ", 0) == 0) << r.out;
  std::ifstream f(out / "run.log");
  const std::string log((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  EXPECT_TRUE(has(log, "|INFO |asf] step 50 ")) << log;
  r = asf(run + " -v INFO");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_TRUE(has(r.out, "|INFO |asf] step 50 ")) << r.out;
  fs::remove_all(out);
}

// An asf::Error thrown inside a plugin reaches the host's error message intact: the
// registry unloads the plugin while the exception unwinds, and the exception's vtable and type
// information must not live in the unloaded file (they used to: SIGSEGV, empty message).
TEST(Host, AnErrorThrownInsideAPluginIsPrinted) {
  const fs::path out = fs::temp_directory_path() / "asf_host_plugin_error";
  fs::remove_all(out);
  const auto r = asf("run " ASF_TEST_SOURCE_DIR "/configs/two_rooms_scripted.ini --out " +
                     out.string() + " --set dense_gn.max_nodes=10 -v WARN");
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_TRUE(has(r.out, "exceeds max_nodes = 10")) << r.out;
  EXPECT_TRUE(fs::exists(out / "config.ini")) << "what the run wrote before the error is kept";
  fs::remove_all(out);
}

// [pipeline] snapshot_distances (thesis fig. 6.1): the map, regions and graph as they stood
// when the robot had driven each distance; one not reached writes nothing; a bad list is a
// configuration error naming the key.
TEST(Host, RunWritesSnapshotsAtTheDistancesAsked) {
  const fs::path out = fs::temp_directory_path() / "asf_host_snapshots";
  fs::remove_all(out);
  const std::string run = "run " ASF_TEST_SOURCE_DIR "/configs/two_rooms_scripted.ini --out " +
                          out.string() + " --set pipeline.max_steps=200 -v WARN";
  auto r = asf(run + " --set pipeline.snapshot_distances=2.5,0.5,1000");
  ASSERT_EQ(r.code, 0) << r.out;
  for (const char* d : {"0.5", "2.5"})
    for (const char* f : {"map.png", "regions.png", "topology.svg"})
      EXPECT_TRUE(fs::exists(out / "snapshots" / ("at_" + std::string(d) + "m_" + f))) << d << f;
  EXPECT_FALSE(fs::exists(out / "snapshots" / "at_1000m_map.png"));
  // The two snapshots differ: the map grew in between.
  EXPECT_NE(fs::file_size(out / "snapshots/at_0.5m_map.png"),
            fs::file_size(out / "snapshots/at_2.5m_map.png"));
  r = asf(run + " --set pipeline.snapshot_distances=2,x");
  EXPECT_EQ(r.code, 1);
  EXPECT_TRUE(has(r.out, "snapshot_distances")) << r.out;
  fs::remove_all(out);
}

TEST(Host, ConformanceByNameAndByFile) {
  auto r = asf("conformance waypoints --gtest_brief=1");
  EXPECT_EQ(r.code, 0) << r.out;
  r = asf("conformance " ASF_TEST_BINARY_DIR "/tests/plugins/no_entry/no_entry_lib.so");
  EXPECT_EQ(r.code, 1);
  EXPECT_TRUE(has(r.out, "not an asf plugin")) << r.out;
  r = asf("conformance nosuchplugin");
  EXPECT_EQ(r.code, 1);
  EXPECT_TRUE(has(r.out, "unknown plugin 'nosuchplugin'; available:")) << r.out;
}

namespace {

// The value of `key = value` in an INI's text ("" if absent).
std::string iniValue(const std::string& text, const std::string& key) {
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    const auto eq = line.find('=');
    if (line.empty() || line[0] == ';' || eq == std::string::npos) continue;
    std::string k = line.substr(0, eq);
    k.erase(k.find_last_not_of(" \t") + 1);
    if (k != key) continue;
    std::string v = line.substr(eq + 1);
    v.erase(0, v.find_first_not_of(" \t"));
    return v;
  }
  return "";
}

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, sep)) {
    item.erase(0, item.find_first_not_of(" \t"));
    item.erase(item.find_last_not_of(" \t") + 1);
    if (!item.empty()) out.push_back(item);
  }
  return out;
}

}  // namespace

// Every shipped configuration is valid as shipped: pipeline INIs pass `asf config` (unknown
// keys, bad values and missing plugins are errors there), and each experiment INI's pipeline
// does with every policy it names and its overrides applied.
TEST(Host, ShippedConfigsAreValid) {
  const fs::path dir = fs::path(ASF_TEST_SOURCE_DIR) / "configs";
  int checked = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.path().extension() != ".ini") continue;
    std::ifstream in(entry.path());
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    SCOPED_TRACE(entry.path().string());
    if (has(text, "[plan_eval]")) continue;  // checked by test_plan_eval
    if (!has(text, "[experiment]")) {
      const auto r = asf("config " + entry.path().string());
      EXPECT_EQ(r.code, 0) << r.out;
      ++checked;
      continue;
    }
    const fs::path pipeline = dir / iniValue(text, "pipeline");
    ASSERT_TRUE(fs::exists(pipeline)) << pipeline;
    std::string sets;
    for (const auto& o : split(iniValue(text, "overrides"), ';')) sets += " --set " + o;
    for (const auto& policy : split(iniValue(text, "policies"), ',')) {
      const auto r = asf("config " + pipeline.string() + " --set pipeline.policy=" + policy + sets);
      EXPECT_EQ(r.code, 0) << policy << ": " << r.out;
    }
    ++checked;
  }
  EXPECT_GE(checked, 10);
}
