// INI parsing and validation against key tables: every error names file:line, section, key.
#include <asf/config.h>
#include <asf/errors.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "test_util.h"

using asf::ConfigError;
using asf::IniConfig;
using asf::KeySpec;

using asf_test::has;
namespace {
const auto errorOf = asf_test::errorOf<asf::ConfigError>;
}
namespace {

const KeySpec kKeys[] = {
    asf::keyDouble("max_range", "8.0", "Laser range [m]", 0.1, 100.0),
    asf::keyInt("rays", "181", "Rays per scan", 1, 10000),
    asf::keyBool("enabled", "true", "On or off"),
    asf::keyEnum("mode", "fast", "fast|exact", "How"),
    asf::keyString("label", nullptr, "Required label"),
    asf::keyPath("map", "", "A file"),
    asf::keyDoubleList("weights", "1 2 3", "Weights", 0.0, 10.0),
};

}  // namespace

TEST(IniConfig, ResolvesValuesDefaultsAndTypes) {
  const auto ini = IniConfig::fromText(
      "; a comment\n[Sensor]\nMax_Range = 5.5 // inline comment\nlabel = front\n"
      "mode = exact\nweights = 0.5, 1.5\nenabled = off\n",
      "s.ini");
  const auto p = ini.resolve("sensor", kKeys, std::size(kKeys));
  EXPECT_DOUBLE_EQ(p.getDouble("max_range"), 5.5);
  EXPECT_FALSE(p.isDefault("max_range"));
  EXPECT_EQ(p.getInt("rays"), 181);
  EXPECT_TRUE(p.isDefault("rays"));
  EXPECT_FALSE(p.getBool("enabled"));
  EXPECT_EQ(p.getString("mode"), "exact");
  EXPECT_EQ(p.getString("label"), "front");
  EXPECT_EQ(p.getDoubleList("weights"), (std::vector<double>{0.5, 1.5}));
}

TEST(IniConfig, UnknownKeyNamesFileLineSectionAndSuggests) {
  const auto ini = IniConfig::fromText("[sensor]\nlabel = x\n\nmax_rnage = 3\n", "cfg.ini");
  const std::string msg = errorOf([&] { ini.resolve("sensor", kKeys, std::size(kKeys)); });
  EXPECT_TRUE(has(msg, "cfg.ini:4: [sensor] unknown key 'max_rnage' (did you mean 'max_range'?)"))
      << msg;
}

TEST(IniConfig, MissingRequiredKeyIsAnError) {
  const auto ini = IniConfig::fromText("[sensor]\nrays = 3\n", "cfg.ini");
  const std::string msg = errorOf([&] { ini.resolve("sensor", kKeys, std::size(kKeys)); });
  EXPECT_TRUE(has(msg, "cfg.ini:1: [sensor] missing required key 'label'")) << msg;
}

TEST(IniConfig, BadValuesAreReportedAllAtOnce) {
  const auto ini = IniConfig::fromText(
      "[sensor]\nlabel = x\nmax_range = far\nrays = 0\nmode = slow\nenabled = maybe\n"
      "weights = 1 20\n",
      "cfg.ini");
  const std::string msg = errorOf([&] { ini.resolve("sensor", kKeys, std::size(kKeys)); });
  EXPECT_TRUE(has(msg, "cfg.ini:3: [sensor] max_range = 'far': not a number")) << msg;
  EXPECT_TRUE(has(msg, "cfg.ini:4: [sensor] rays = '0': out of range [1, 10000]")) << msg;
  EXPECT_TRUE(has(msg, "cfg.ini:5: [sensor] mode = 'slow': not one of fast|exact")) << msg;
  EXPECT_TRUE(has(msg, "cfg.ini:6: [sensor] enabled = 'maybe': not a bool")) << msg;
  EXPECT_TRUE(has(msg, "cfg.ini:7: [sensor] weights = '1 20': item 20 out of range")) << msg;
}

TEST(IniConfig, OverridesWinAndAreNamedInErrors) {
  auto ini = IniConfig::fromText("[sensor]\nlabel = x\nrays = 10\n", "cfg.ini");
  ini.applyOverride("sensor.rays=20");
  ini.applyOverride("Sensor.MAX_RANGE = 2");
  auto p = ini.resolve("sensor", kKeys, std::size(kKeys));
  EXPECT_EQ(p.getInt("rays"), 20);
  EXPECT_DOUBLE_EQ(p.getDouble("max_range"), 2.0);
  ini.applyOverride("sensor.rays=-1");
  const std::string msg = errorOf([&] { ini.resolve("sensor", kKeys, std::size(kKeys)); });
  EXPECT_TRUE(has(msg, "--set sensor.rays: [sensor] rays = '-1': out of range")) << msg;
  EXPECT_TRUE(has(errorOf([&] { ini.applyOverride("norays"); }), "expected section.key=value"));
  EXPECT_TRUE(has(errorOf([&] { ini.applyOverride(".x=1"); }), "expected section.key=value"));
}

TEST(IniConfig, MrptPreprocessorWorks) {
  const auto ini = IniConfig::fromText(
      "@define RANGE 4\n[sensor]\nlabel = x\nmax_range = ${RANGE}\nrays = $eval{RANGE*10}\n",
      "cfg.ini");
  const auto p = ini.resolve("sensor", kKeys, std::size(kKeys));
  EXPECT_DOUBLE_EQ(p.getDouble("max_range"), 4.0);
  EXPECT_EQ(p.getInt("rays"), 40);
}

TEST(IniConfig, SyntaxErrorsNameTheLine) {
  EXPECT_TRUE(has(errorOf([] { IniConfig::fromText("[a]\nx = 1\nnot a key value\n", "bad.ini"); }),
                  "bad.ini:3: expected 'key = value'"));
  EXPECT_TRUE(has(errorOf([] { IniConfig::fromText("[a\nx = 1\n", "bad.ini"); }),
                  "bad.ini:1: unterminated section header"));
  EXPECT_TRUE(has(errorOf([] { IniConfig::fromText("x = 1\n[a]\n", "bad.ini"); }),
                  "bad.ini:1: key 'x' before any [section]"));
  EXPECT_TRUE(has(errorOf([] { IniConfig::fromFile("/nonexistent/asf.ini"); }),
                  "/nonexistent/asf.ini: cannot open"));
}

// Issue 51, items 6 and 7: a file that never ends is refused after 16 MiB, naming it; a UTF-8
// byte order mark (Windows editors) is no syntax error.
TEST(IniConfig, HugeFilesAreRefusedUnreadAndAByteOrderMarkIsSkipped) {
  const std::string e = errorOf([] { IniConfig::fromFile("/dev/zero"); });
  EXPECT_TRUE(has(e, "/dev/zero: larger than 16 MiB")) << e;
  const std::string text = "[pipeline]\nseed = 7\n[sim2d]\nrays = 5\n";
  const IniConfig plain = IniConfig::fromText(text, "plain.ini");
  const IniConfig bom = IniConfig::fromText("\xEF\xBB\xBF" + text, "bom.ini");
  EXPECT_EQ(bom.get("pipeline", "seed"), "7");
  EXPECT_EQ(bom.get("sim2d", "rays"), plain.get("sim2d", "rays"));
  const auto dir = asf_test::freshTempDir("asf_test_config_bom");
  asf_test::writeFile(dir / "bom.ini", "\xEF\xBB\xBF" + text);
  EXPECT_EQ(IniConfig::fromFile((dir / "bom.ini").string()).get("pipeline", "seed"), "7");
}

// Issue 20, item 3: what MRPT would drop or overwrite silently is an error naming the line.
TEST(IniConfig, NulBytesRepeatedKeysAndUnknownDirectivesAreErrors) {
  // A NUL byte: MRPT stops reading there, so `seed` and every later key would be defaults.
  const std::string with_nul =
      std::string("[run]\nlabel = x\nseed = 1") + '\0' + std::string("junk\nrays = 5\n");
  ASSERT_EQ(with_nul.find('\0'), 24u);
  EXPECT_TRUE(
      has(errorOf([&] { IniConfig::fromText(with_nul, "nul.ini"); }), "nul.ini:3: a NUL byte"));
  // A repeated key, also across two blocks of one section (case-insensitive).
  EXPECT_TRUE(has(errorOf([] { IniConfig::fromText("[a]\nx = 1\ny = 2\nx = 3\n", "dup.ini"); }),
                  "dup.ini:4: key 'x' of [a] is already set at line 2"));
  EXPECT_TRUE(
      has(errorOf([] { IniConfig::fromText("[a]\nX = 1\n[b]\nx = 2\n[A]\nx = 3\n", "dup.ini"); }),
          "dup.ini:6: key 'x' of [a] is already set at line 2"));
  // The same key in two sections is fine.
  EXPECT_NO_THROW(IniConfig::fromText("[a]\nx = 1\n[b]\nx = 2\n", "ok.ini"));
  // @define is MRPT's directive; @include and the like are not, and would be skipped.
  EXPECT_TRUE(
      has(errorOf([] { IniConfig::fromText("@include other.ini\n[a]\nx = 1\n", "inc.ini"); }),
          "inc.ini:1: unknown directive '@include'"));
  EXPECT_NO_THROW(IniConfig::fromText("@define R 4\n[a]\nx = ${R}\n", "def.ini"));
}

TEST(IniConfig, RelativePathsResolveAgainstTheIniFolder) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / "asf_test_config";
  fs::create_directories(dir);
  { std::ofstream(dir / "c.ini") << "[sensor]\nlabel = x\nmap = maps/world.png\n"; }
  const auto ini = IniConfig::fromFile((dir / "c.ini").string());
  const auto p = ini.resolve("sensor", kKeys, std::size(kKeys));
  EXPECT_EQ(p.getString("map"), (dir / "maps/world.png").string());
  fs::remove_all(dir);
}

TEST(Params, FromSpecsValidatesOverrides) {
  auto p = asf::Params::fromSpecs("sensor", kKeys, std::size(kKeys), {{"label", "a"}});
  EXPECT_DOUBLE_EQ(p.getDouble("max_range"), 8.0);
  EXPECT_TRUE(has(errorOf([] {
                    asf::Params::fromSpecs("sensor", kKeys, std::size(kKeys),
                                           {{"label", "a"}, {"max_range", "1000"}});
                  }),
                  "max_range = '1000': out of range [0.1, 100]"));
  EXPECT_TRUE(has(errorOf([] { asf::Params::fromSpecs("sensor", kKeys, std::size(kKeys)); }),
                  "missing required key 'label'"));
  EXPECT_TRUE(has(
      errorOf([] {
        asf::Params::fromSpecs("sensor", kKeys, std::size(kKeys), {{"label", "a"}, {"nope", "1"}});
      }),
      "unknown key 'nope'"));
  EXPECT_TRUE(
      has(errorOf([&] { p.fail("rays", "must be even"); }), "[sensor] rays = '181': must be even"));
}

TEST(DidYouMean, SuggestsOnlyCloseWords) {
  EXPECT_EQ(asf::didYouMean("segmentr", {"segmenter", "source"}), "segmenter");
  EXPECT_EQ(asf::didYouMean("xyz", {"segmenter", "source"}), "");
}
