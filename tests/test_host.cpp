// The asf host as a user meets it: subcommands, --help, exit codes, messages.
#include <asf/abi.h>
#include <gtest/gtest.h>

#include "test_util.h"
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <set>
#include <fstream>
#include <nlohmann/json.hpp>

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
  EXPECT_EQ(kinds, (std::set<std::string>{"source", "frontend", "backend", "segmenter",
                                          "planner", "policy"}));
}

TEST(Host, PluginsReportsBrokenFilesWithExitCode1) {
  const auto r = asf("plugins --plugin-path " ASF_TEST_BINARY_DIR "/tests/plugins/wrong_abi");
  EXPECT_EQ(r.code, 1);
  EXPECT_TRUE(has(r.out, "wrong_abi_policy.so: ABI mismatch")) << r.out;
}

TEST(Host, ConfigPrintsDefaultsAndRejectsTypos) {
  auto r = asf("config " ASF_TEST_SOURCE_DIR "/configs/two_rooms_scripted.ini --set map.resolution=0.1");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_TRUE(has(r.out, "resolution = 0.1"));
  EXPECT_TRUE(has(r.out, "[dense_gn]")) << "sections of selected plugins appear with defaults";
  const auto f = writeIni("asf_host_typo.ini",
                          "[pipeline]\nsource = segment_world\nfrontend = odometry\n"
                          "[segment_world]\nlaser_max_rnge = 3\n");
  r = asf("config " + f.string());
  EXPECT_EQ(r.code, 1);
  EXPECT_TRUE(has(r.out, f.string() + ":5: [segment_world] unknown key 'laser_max_rnge' (did you "
                                      "mean 'laser_max_range'?)")) << r.out;
  r = asf("config " + f.string() + " --set bogus");
  EXPECT_EQ(r.code, 1);
  EXPECT_TRUE(has(r.out, "expected section.key=value")) << r.out;
  fs::remove(f);
}

TEST(Host, RunWritesResultsAndSaysWhere) {
  const fs::path out = fs::temp_directory_path() / "asf_host_run";
  fs::remove_all(out);
  const auto r = asf("run " ASF_TEST_SOURCE_DIR "/configs/two_rooms_scripted.ini --out " + out.string() +
                     " --set pipeline.max_steps=50 -v WARN");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_TRUE(has(r.out, "step budget (50) spent")) << r.out;
  EXPECT_TRUE(has(r.out, "results in " + out.string())) << r.out;
  EXPECT_TRUE(fs::exists(out / "summary.json"));
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
