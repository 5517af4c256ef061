// The fuzz targets (fuzz/fuzz_targets.h) on their seed corpus and on the regressions found by
// fuzzing, in the normal test suite: every input is accepted or rejected with an asf::Error,
// nothing else escapes; each corpus has a seed that is accepted (a corpus the parser rejects
// whole would fuzz only its first check); every folder names a target.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <ostream>
#include <string>
#include <vector>

#include "fuzz_targets.h"

namespace asf::fuzz {
// Test names and failure messages show the target's name, not its bytes.
void PrintTo(const Target& t, std::ostream* os) { *os << t.name; }
}  // namespace asf::fuzz

namespace {

namespace fs = std::filesystem;

const fs::path kFuzzDir = fs::path(ASF_TEST_SOURCE_DIR) / "fuzz";

std::vector<std::uint8_t> readBytes(const fs::path& f) {
  std::ifstream in(f, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::vector<fs::path> filesIn(const fs::path& dir) {
  std::vector<fs::path> out;
  if (fs::is_directory(dir))
    for (const auto& e : fs::directory_iterator(dir))
      if (e.is_regular_file()) out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

class FuzzCorpus : public ::testing::TestWithParam<asf::fuzz::Target> {};

TEST_P(FuzzCorpus, SeedsAndRegressionsAreAcceptedOrRejectedCleanly) {
  const auto& t = GetParam();
  const auto seeds = filesIn(kFuzzDir / "corpus" / t.name);
  ASSERT_FALSE(seeds.empty()) << "no seed in fuzz/corpus/" << t.name;
  int accepted = 0;
  for (const auto& f : seeds) {
    const auto bytes = readBytes(f);
    try {
      accepted += t.run(bytes.data(), bytes.size()) ? 1 : 0;
    } catch (const std::exception& e) {
      ADD_FAILURE() << f << ": " << e.what();
    }
  }
  EXPECT_GT(accepted, 0) << "every seed of " << t.name << " is rejected";
  for (const auto& f : filesIn(kFuzzDir / "regressions" / t.name)) {
    const auto bytes = readBytes(f);
    try {
      t.run(bytes.data(), bytes.size());
    } catch (const std::exception& e) {
      ADD_FAILURE() << f << ": " << e.what();
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Targets, FuzzCorpus, ::testing::ValuesIn(asf::fuzz::targets()),
                         [](const auto& info) { return std::string(info.param.name); });

TEST(FuzzCorpusFolders, EveryFolderNamesATarget) {
  for (const char* kind : {"corpus", "regressions"}) {
    if (!fs::is_directory(kFuzzDir / kind)) continue;
    for (const auto& e : fs::directory_iterator(kFuzzDir / kind))
      EXPECT_NE(asf::fuzz::findTarget(e.path().filename().string()), nullptr)
          << e.path() << " names no fuzz target (fuzz/fuzz_targets.cpp)";
  }
}

}  // namespace
