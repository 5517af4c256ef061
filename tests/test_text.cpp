// The shared text helpers (asf/text.h) against the standard library formatting each call site
// used before they were shared, and the one wording of an unknown INI section.
#include <asf/config.h>
#include <asf/text.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <iomanip>
#include <limits>
#include <random>
#include <sstream>
#include <thread>

namespace {

std::string iostreamFixed(double v, int digits) {
  std::ostringstream os;
  os << std::fixed << std::setprecision(digits) << v;
  return os.str();
}

std::string printfG(double v, int digits) {
  char b[64];
  std::snprintf(b, sizeof b, "%.*g", digits, v);
  return b;
}

std::vector<double> sampleValues() {
  std::vector<double> v = {0.0,
                           -0.0,
                           0.5,
                           1.5,
                           2.5,
                           -2.5,
                           0.125,
                           1e-9,
                           1e300,
                           -1e300,
                           123.456,
                           0.0049,
                           0.0051,
                           99.995,
                           1e21,
                           -7.25e-5,
                           std::numeric_limits<double>::infinity(),
                           -std::numeric_limits<double>::infinity(),
                           std::numeric_limits<double>::denorm_min(),
                           std::numeric_limits<double>::max()};
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> mant(-10, 10);
  std::uniform_int_distribution<int> ex(-30, 30);
  for (int i = 0; i < 2000; ++i) v.push_back(mant(rng) * std::pow(10.0, ex(rng)));
  return v;
}

TEST(Text, TrimRemovesEveryKindOfWhiteSpaceAtBothEndsOnly) {
  EXPECT_EQ(asf::trim(""), "");
  EXPECT_EQ(asf::trim(" \t\r\n\f\v"), "");
  EXPECT_EQ(asf::trim("  a b\t"), "a b");
  EXPECT_EQ(asf::trim("\r\nkey = value \r"), "key = value");
  EXPECT_EQ(asf::trim("x"), "x");
  EXPECT_EQ(asf::trim("\va\f"), "a");
}

TEST(Text, SplitTrimmedKeepsTheTrimmedNonEmptyItemsInOrder) {
  using V = std::vector<std::string>;
  EXPECT_EQ(asf::splitTrimmed(" a.b=1;  c = 2 ;; \t;d", ';'), (V{"a.b=1", "c = 2", "d"}));
  EXPECT_EQ(asf::splitTrimmed("tigre, frontier,", ','), (V{"tigre", "frontier"}));
  EXPECT_EQ(asf::splitTrimmed("x;y", ','), (V{"x;y"}));
  EXPECT_TRUE(asf::splitTrimmed(" ; ;", ';').empty());
  EXPECT_TRUE(asf::splitTrimmed("", ';').empty());
}

TEST(Text, FormatFixedPrintsAsIostreamsFixed) {
  for (double v : sampleValues())
    for (int digits : {0, 1, 2, 3, 6, 17}) {
      if (std::abs(v) > 1e200 && digits > 6) continue;  // both fine; keeps the test short
      EXPECT_EQ(asf::formatFixed(v, digits), iostreamFixed(v, digits)) << v << " " << digits;
    }
  EXPECT_EQ(asf::formatFixed(2.5, 0), "2");  // round half to even, as printf
  EXPECT_EQ(asf::formatFixed(-0.0, 2), "-0.00");
  EXPECT_EQ(asf::formatFixed(std::numeric_limits<double>::quiet_NaN(), 1), "nan");
}

TEST(Text, FormatSignificantPrintsAsPrintfG) {
  for (double v : sampleValues())
    for (int digits : {1, 3, 6, 8, 17})
      EXPECT_EQ(asf::formatSignificant(v, digits), printfG(v, digits)) << v << " " << digits;
  EXPECT_EQ(asf::formatSignificant(0.1, 17), "0.10000000000000001");
  EXPECT_EQ(asf::formatSignificant(1234567.0, 6), "1.23457e+06");
}

TEST(Text, HtmlEscapeEscapesTheFourSpecialCharacters) {
  EXPECT_EQ(asf::htmlEscape("a<b & \"c\">d'"), "a&lt;b &amp; &quot;c&quot;&gt;d'");
  EXPECT_EQ(asf::htmlEscape(""), "");
  EXPECT_EQ(asf::htmlEscape("&amp;"), "&amp;amp;");  // escaped again: the input is text
}

TEST(Text, MsSinceMeasuresElapsedTime) {
  const auto t0 = std::chrono::steady_clock::now();
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  const double ms = asf::msSince(t0);
  EXPECT_GE(ms, 20.0);
  EXPECT_LT(ms, 60000.0);
}

TEST(IniConfigUnknownSection, NamesFileLineSectionHintAndWhatIsExpected) {
  const auto ini = asf::IniConfig::fromText("[pipeline]\nseed = 1\n\n[segmnter]\nx = 1\n", "a.ini");
  EXPECT_EQ(ini.unknownSection("segmnter", {"pipeline", "segmenter"}, "sections are X"),
            "a.ini:4: unknown section [segmnter] (did you mean [segmenter]?); sections are X");
  EXPECT_EQ(ini.unknownSection("segmnter", {"pipeline"}, "only [pipeline]"),
            "a.ini:4: unknown section [segmnter]; only [pipeline]");
}

}  // namespace
