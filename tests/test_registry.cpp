// The registry's error paths, on real plugin files built by the test suite.
#include <asf/policy.h>
#include <asf/source.h>
#include <asf/framework/registry.h>
#include <gtest/gtest.h>

#include "test_util.h"

#include <filesystem>
#include <fstream>

using asf_test::has;
namespace {
const auto errorOf = asf_test::errorOf<asf::PluginError>;
}
namespace fs = std::filesystem;
using asf::PluginError;
using asf::framework::Registry;

namespace {
const std::string kDir = ASF_TEST_BINARY_DIR "/tests/plugins";

}  // namespace

TEST(Registry, LoadsAGoodPluginAndCreatesIt) {
  auto info = asf::framework::Registry::loadFile(kDir + "/good/good_policy.so");
  EXPECT_EQ(info->name(), "test_policy");
  EXPECT_EQ(info->kind(), asf::PluginKind::Policy);
  EXPECT_EQ(info->descriptor->abi_version, ASF_ABI_VERSION);
  ASSERT_NE(info->findKey("fail_after"), nullptr);
  auto h = asf::framework::Registry::create<asf::Policy>(info);
  ASSERT_TRUE(h);
  const auto* d = info->descriptor;
  h->configure(asf::Params::fromSpecs("test_policy", d->keys, d->num_keys), {});
  asf::TopoGraph topo;
  asf::ExplorationState s;
  s.topo = &topo;
  EXPECT_EQ(h->decide(s).type, asf::Decision::Type::Done);
}

TEST(Registry, CreateChecksTheKind) {
  auto info = asf::framework::Registry::loadFile(kDir + "/good/good_policy.so");
  const std::string msg = errorOf([&] { asf::framework::Registry::create<asf::Source>(info); });
  EXPECT_NE(msg.find("is a policy, not a source"), std::string::npos) << msg;
}

TEST(Registry, WrongAbiNamesFileAndBothVersions) {
  const std::string file = kDir + "/wrong_abi/wrong_abi_policy.so";
  const std::string msg = errorOf([&] { asf::framework::Registry::loadFile(file); });
  EXPECT_NE(msg.find(fs::canonical(file).string()), std::string::npos) << msg;
  EXPECT_NE(msg.find("ABI mismatch"), std::string::npos) << msg;
  EXPECT_NE(msg.find("ABI " + std::to_string(ASF_ABI_VERSION + 41)), std::string::npos) << msg;
  EXPECT_NE(msg.find("host has ABI " + std::to_string(ASF_ABI_VERSION)), std::string::npos) << msg;
}

TEST(Registry, MissingEntryPointIsNotAPlugin) {
  const std::string file = kDir + "/no_entry/no_entry_lib.so";
  const std::string msg = errorOf([&] { asf::framework::Registry::loadFile(file); });
  EXPECT_NE(msg.find("not an asf plugin"), std::string::npos) << msg;
  EXPECT_NE(msg.find("no_entry_lib.so"), std::string::npos) << msg;
}

TEST(Registry, ThrowingFactoryReportsFileAndMessage) {
  auto info =
      asf::framework::Registry::loadFile(kDir + "/throwing_factory/throwing_factory_policy.so");
  const std::string msg = errorOf([&] { asf::framework::Registry::create<asf::Policy>(info); });
  EXPECT_NE(msg.find("factory threw"), std::string::npos) << msg;
  EXPECT_NE(msg.find("cannot open the device /dev/nowhere"), std::string::npos) << msg;
  EXPECT_NE(msg.find("throwing_factory_policy.so"), std::string::npos) << msg;
}

TEST(Registry, DuplicateNamesNameBothFiles) {
  asf::framework::Registry reg;
  EXPECT_EQ(reg.scanDirectory(kDir + "/duplicate"), 1);
  ASSERT_EQ(reg.problems().size(), 1u);
  EXPECT_NE(reg.problems()[0].find("two plugins named 'dup_policy'"), std::string::npos);
  const std::string msg = errorOf([&] { reg.find("dup_policy", asf::PluginKind::Policy); });
  EXPECT_NE(msg.find("duplicate_a_policy.so"), std::string::npos) << msg;
  EXPECT_NE(msg.find("duplicate_b_policy.so"), std::string::npos) << msg;
}

TEST(Registry, SameFileTwiceIsNotADuplicate) {
  asf::framework::Registry reg;
  reg.scanDirectory(kDir + "/good");
  reg.scanDirectory(kDir + "/good/../good");
  EXPECT_EQ(reg.plugins().size(), 1u);
  EXPECT_TRUE(reg.problems().empty());
}

TEST(Registry, UnknownNameListsAvailablePluginsOfThatKind) {
  asf::framework::Registry reg;
  reg.scanDirectory(kDir + "/good");
  std::string msg = errorOf([&] { reg.find("tigre", asf::PluginKind::Policy); });
  EXPECT_NE(msg.find("unknown policy plugin 'tigre'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("available policy plugins: test_policy"), std::string::npos) << msg;
  msg = errorOf([&] { reg.find("test_policy", asf::PluginKind::Backend); });
  EXPECT_NE(msg.find("is a policy, not a backend"), std::string::npos) << msg;
}

TEST(Registry, BadDescriptorIsRejected) {
  const std::string msg =
      errorOf([&] { asf::framework::Registry::loadFile(kDir + "/bad_name/bad_name_policy.so"); });
  EXPECT_NE(msg.find("bad descriptor: plugin name must be lower_snake_case"), std::string::npos)
      << msg;
}

TEST(Registry, FileThatIsNotALibraryCannotBeLoaded) {
  const fs::path dir = fs::temp_directory_path() / "asf_test_registry_junk";
  fs::create_directories(dir);
  { std::ofstream(dir / "junk.so") << "this is not an ELF file\n"; }
  asf::framework::Registry reg;
  EXPECT_EQ(reg.scanDirectory(dir.string()), 0);
  ASSERT_EQ(reg.problems().size(), 1u);
  EXPECT_NE(reg.problems()[0].find("junk.so: cannot load"), std::string::npos) << reg.problems()[0];
  EXPECT_NE(errorOf([&] { asf::framework::Registry::loadFile((dir / "missing.so").string()); })
                .find("no such plugin file"),
            std::string::npos);
  fs::remove_all(dir);
}

TEST(Registry, ScansTheBuildTreeAndAsfPluginPath) {
  // The test binary lives in build/tests, so <exe>/../lib/asf/plugins is the build tree's
  // plugin folder: the reference plugins.
  setenv("ASF_PLUGIN_PATH", (kDir + "/good:/nonexistent").c_str(), 1);
  const auto dirs = asf::framework::Registry::defaultSearchPath();
  unsetenv("ASF_PLUGIN_PATH");
  ASSERT_EQ(dirs.size(), 3u);
  EXPECT_EQ(fs::canonical(dirs[0]), fs::canonical(ASF_TEST_PLUGIN_DIR));
  EXPECT_EQ(dirs[1], kDir + "/good");
  asf::framework::Registry reg;
  for (const auto& d : dirs) reg.scanDirectory(d);
  EXPECT_TRUE(reg.problems().empty()) << reg.problems()[0];
  for (int k = 0; k < asf::kNumPluginKinds; ++k)
    EXPECT_FALSE(reg.names(static_cast<asf::PluginKind>(k)).empty())
        << "no " << asf::kindName(static_cast<asf::PluginKind>(k)) << " plugin in the tree";
  EXPECT_NE(reg.find("test_policy"), nullptr);
}
