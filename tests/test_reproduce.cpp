// asf reproduce --quick: every table and figure of chapters 3-6 gets a row with the thesis'
// value and asf's, the report's three files have their structure, and a second run resumes
// (keeps every stage, same rows). The values themselves are smoke-run sizes and not checked.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "test_util.h"

namespace fs = std::filesystem;
using asf_test::has;
using asf_test::runHost;

namespace {

std::string readFile(const fs::path& p) {
  std::ifstream in(p);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

const std::string kShared = ASF_TEST_SHARED_DIR;
const std::string kConfigs = std::string(ASF_TEST_SOURCE_DIR) + "/configs";

}  // namespace

TEST(Reproduce, QuickGivesEveryRowBothValuesAndResumes) {
  for (const char* f :
       {"datasets/carmen/intel-corrected.log.gz", "datasets/carmen/aces-corrected.log.gz",
        "datasets/roomseg/plain", "datasets/optexp/graphs.txt", "datasets/g2o/MIT.g2o"})
    if (!fs::exists(kShared + "/" + f))
      GTEST_SKIP() << kShared << "/" << f << " not found (../shared)";
  const fs::path out = fs::temp_directory_path() / ("asf_reproduce_" + std::to_string(::getpid()));
  fs::remove_all(out);
  const std::string args =
      "reproduce --quick -o " + out.string() + " --shared " + kShared + " --configs " + kConfigs;
  const auto first = runHost(args);
  ASSERT_EQ(first.code, 0) << first.out;
  EXPECT_TRUE(has(first.out, "0 without an asf value")) << first.out;

  const auto j = nlohmann::json::parse(readFile(out / "report.json"));
  EXPECT_TRUE(j["settings"]["quick"].get<bool>());
  for (const auto& st : j["stages"]) EXPECT_EQ(st["status"], "done") << st.dump();
  std::set<std::string> sections;
  for (const auto& row : j["rows"]) {
    sections.insert(row["section"].get<std::string>());
    EXPECT_FALSE(row["thesis"].get<std::string>().empty()) << row.dump();
    EXPECT_FALSE(row["asf"].get<std::string>().empty()) << row.dump();
    EXPECT_FALSE(row["difference"].get<std::string>().empty()) << row.dump();
  }
  for (const char* s :
       {"Figs. 3.1-3.2", "Fig. 3.3",  "Table 3.1", "Fig. 3.4",      "Fig. 3.5",
        "Table 3.2",     "Table 4.1", "Fig. 4.1",  "Fig. 4.2",      "Fig. 4.3",
        "Fig. 4.4",      "Fig. 4.5",  "Table 5.1", "Theorem 5.2.1", "Figs. 5.5-5.10",
        "Fig. 5.11",     "Fig. 5.12", "Fig. 5.13", "Figs. 6.2-6.4", "Fig. 6.1"})
    EXPECT_EQ(sections.count(s), 1u) << "no row for " << s;
  // 2 logs x (16 cells + 2 claims) of Table 3.1, 12 cells of Table 4.1 and, with the reference
  // DuDe's outputs in the data, 2 scenarios x (2 of them scored + 1 comparison), 4 policies x 3
  // of ch. 6.
  std::size_t t31 = 0, t41 = 0, reference = 0;
  for (const auto& row : j["rows"]) {
    t31 += row["section"] == "Table 3.1";
    t41 += row["section"] == "Table 4.1";
    reference += row["section"] == "Table 4.1" &&
                 has(row["item"].get<std::string>(), "reference");
  }
  EXPECT_EQ(t31, 36u);
  const bool has_reference = fs::is_directory(kShared + "/datasets/roomseg/reference_dude");
  EXPECT_EQ(reference, has_reference ? 6u : 0u);
  EXPECT_EQ(t41, 12u + reference);
  // Fig. 3.4: both zones of both logs drawn (scenarios A and C).
  std::set<std::string> figures;
  for (const auto& f : j["figures"]) figures.insert(f["file"].get<std::string>());
  for (const char* log : {"intel", "aces"})
    for (const char* sc : {"A", "C"})
      EXPECT_EQ(figures.count(std::string("ch3_table_3_1_") + log + "/scenario_" + sc + ".svg"), 1u)
          << log << " " << sc;
  std::size_t svg = 0, png = 0;
  for (const auto& f : j["figures"]) {
    const fs::path p = out / f["file"].get<std::string>();
    EXPECT_TRUE(fs::exists(p)) << p;
    (p.extension() == ".svg" ? svg : png) += 1;
  }
  EXPECT_GE(svg, 10u);
  EXPECT_GE(png, 10u);

  const std::string md = readFile(out / "report.md"), html = readFile(out / "report.html");
  EXPECT_TRUE(has(md, "| figure | thesis value | asf value | difference | note |"));
  EXPECT_TRUE(has(md, "## Table 3.1")) << md.substr(0, 500);
  EXPECT_TRUE(has(html, "<svg"));
  EXPECT_TRUE(has(html, "data:image/png;base64,"));
  EXPECT_TRUE(has(html, "<th>thesis value</th>"));

  // Resume: every stage kept, the same rows.
  const auto second = runHost(args);
  ASSERT_EQ(second.code, 0) << second.out;
  const std::size_t n = j["stages"].size();
  EXPECT_TRUE(
      has(second.out, std::to_string(n) + " of " + std::to_string(n) + " stages done before"))
      << second.out;
  const auto j2 = nlohmann::json::parse(readFile(out / "report.json"));
  EXPECT_EQ(j2["rows"], j["rows"]);

  // Other pairs: only the two Table 3.1 stages depend on them and are done again.
  const auto third = runHost(args + " --pairs 3");
  ASSERT_EQ(third.code, 0) << third.out;
  EXPECT_TRUE(has(third.out, std::to_string(n - 2) + " of " + std::to_string(n) + " stages done"))
      << third.out;
  EXPECT_TRUE(has(third.out, "ch3_table_3_1_aces was begun with 'data=")) << third.out;
  const auto j3 = nlohmann::json::parse(readFile(out / "report.json"));
  for (const auto& row : j3["rows"]) {
    if (row["section"] == "Table 3.1" && has(row["item"].get<std::string>(), ", scenario ")) {
      EXPECT_TRUE(has(row["asf"].get<std::string>(), " of 3)")) << row.dump();
    }
  }
  fs::remove_all(out);
}

TEST(Reproduce, BadFoldersAreNamed) {
  const auto no_shared =
      runHost("reproduce --quick -o /tmp/asf_reproduce_x --shared /nonexistent/data");
  EXPECT_EQ(no_shared.code, 1);
  EXPECT_TRUE(has(no_shared.out, "/nonexistent/data: no such folder")) << no_shared.out;
  const auto no_configs =
      runHost("reproduce --quick -o /tmp/asf_reproduce_x --shared /tmp --configs /tmp");
  EXPECT_EQ(no_configs.code, 1);
  EXPECT_TRUE(has(no_configs.out, "--configs /tmp: no cave_thesis.ini")) << no_configs.out;
}
