// Mutation sweeps (issue 20): damaged g2o files through `asf optimize` and damaged INI files
// through `asf config`, as a user would feed them. Every mutant must be accepted (exit 0) or
// rejected with exit 1 or 2 and a message naming the file; a crash (signal), a hang (killed
// after 60 s) or a rejection that does not name the file fails the test.
//
// The count is ASF_MUTATIONS (default 40 per format, what CI runs) and the seed
// ASF_MUTATION_SEED (default 20); the issue's sweep is ASF_MUTATIONS=500 (docs/RELIABILITY.md).
// Mutants that fail are kept in <temp>/asf_mutation_sweep/ to be rerun by hand.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "test_util.h"

namespace {

namespace fs = std::filesystem;

std::string readText(const fs::path& f) { return asf_test::readFile(f.string()); }

std::vector<std::string> splitLines(const std::string& s) {
  std::vector<std::string> lines;
  std::istringstream in(s);
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  return lines;
}

std::string joinLines(const std::vector<std::string>& lines) {
  std::string s;
  for (const auto& l : lines) s += l + '\n';
  return s;
}

// Tokens that break parsers: non-finite and huge numbers, ids out of range, signs, empty.
const std::vector<std::string> kNastyTokens = {"nan",
                                               "inf",
                                               "-inf",
                                               "1e308",
                                               "-1e308",
                                               "1e-320",
                                               "0",
                                               "-1",
                                               "4294967296",
                                               "2147483648",
                                               "-2147483649",
                                               "99999999999999999999999",
                                               "0x10",
                                               "1,5",
                                               "",
                                               "x",
                                               "#",
                                               ";",
                                               "=",
                                               "[",
                                               "]",
                                               "${undefined}",
                                               "$eval{1/0}",
                                               "$env{ASF_NO_SUCH_VARIABLE}",
                                               "@include other.ini",
                                               "\t"};

// One to three random damages: bytes changed, inserted or deleted, a token replaced by a
// nasty one, lines deleted, repeated or swapped, the file cut short.
std::string mutate(const std::string& base, std::mt19937_64& rng) {
  std::string s = base;
  auto pick = [&](std::size_t n) {
    return n == 0 ? 0 : std::uniform_int_distribution<std::size_t>(0, n - 1)(rng);
  };
  const int damages = 1 + static_cast<int>(pick(3));
  for (int d = 0; d < damages; ++d) {
    switch (pick(8)) {
      case 0:  // a byte changed to any value (NUL and non-ASCII included)
        if (!s.empty()) s[pick(s.size())] = static_cast<char>(pick(256));
        break;
      case 1: {  // a span deleted
        if (s.empty()) break;
        const auto at = pick(s.size());
        s.erase(at, 1 + pick(20));
        break;
      }
      case 2: {  // random bytes inserted
        std::string junk(1 + pick(8), ' ');
        for (auto& c : junk) c = static_cast<char>(pick(256));
        s.insert(pick(s.size() + 1), junk);
        break;
      }
      case 3: {  // a whitespace-separated token replaced by a nasty one
        std::vector<std::pair<std::size_t, std::size_t>> tokens;
        for (std::size_t i = 0; i < s.size();) {
          while (i < s.size() && std::isspace(static_cast<unsigned char>(s[i]))) ++i;
          const auto b = i;
          while (i < s.size() && !std::isspace(static_cast<unsigned char>(s[i]))) ++i;
          if (i > b) tokens.emplace_back(b, i - b);
        }
        if (tokens.empty()) break;
        const auto [b, n] = tokens[pick(tokens.size())];
        s.replace(b, n, kNastyTokens[pick(kNastyTokens.size())]);
        break;
      }
      case 4: {  // a line deleted
        auto lines = splitLines(s);
        if (!lines.empty()) lines.erase(lines.begin() + static_cast<long>(pick(lines.size())));
        s = joinLines(lines);
        break;
      }
      case 5: {  // a line repeated
        auto lines = splitLines(s);
        if (!lines.empty()) {
          const auto i = pick(lines.size());
          lines.insert(lines.begin() + static_cast<long>(pick(lines.size())), lines[i]);
        }
        s = joinLines(lines);
        break;
      }
      case 6: {  // two lines swapped
        auto lines = splitLines(s);
        if (lines.size() > 1) std::swap(lines[pick(lines.size())], lines[pick(lines.size())]);
        s = joinLines(lines);
        break;
      }
      default:  // cut short
        s.resize(pick(s.size() + 1));
    }
  }
  return s;
}

// A pose graph of a square loop, 32 poses, with its loop closures and a FIX line.
std::string baseG2o() {
  std::ostringstream os;
  os.precision(9);
  const int n = 32;
  auto pose = [](int i, double& x, double& y, double& th) {
    const int side = i / 8, k = i % 8;
    const double xs[] = {0, 8, 8, 0}, ys[] = {0, 0, 8, 8};
    const double dx[] = {1, 0, -1, 0}, dy[] = {0, 1, 0, -1};
    x = xs[side] + dx[side] * k;
    y = ys[side] + dy[side] * k;
    th = side * M_PI / 2;
  };
  for (int i = 0; i < n; ++i) {
    double x, y, th;
    pose(i, x, y, th);
    os << "VERTEX_SE2 " << i << ' ' << x + 0.01 * (i % 3) << ' ' << y << ' ' << th << '\n';
  }
  auto edge = [&](int a, int b) {
    double xa, ya, ta, xb, yb, tb;
    pose(a, xa, ya, ta);
    pose(b, xb, yb, tb);
    const double c = std::cos(ta), s = std::sin(ta);
    const double dx = c * (xb - xa) + s * (yb - ya), dy = -s * (xb - xa) + c * (yb - ya);
    os << "EDGE_SE2 " << a << ' ' << b << ' ' << dx << ' ' << dy << ' '
       << std::remainder(tb - ta, 2 * M_PI) << " 100 0 0 100 0 400\n";
  };
  for (int i = 0; i + 1 < n; ++i) edge(i, i + 1);
  edge(n - 1, 0);
  edge(4, 28);
  edge(12, 20);
  os << "FIX 0\n";
  return os.str();
}

struct SweepResult {
  int accepted = 0, rejected = 0, rejected_with_line = 0;
  std::vector<std::string> failures;
};

// Runs `asf <command> <mutant>` on each mutant of each base; each line of failures names
// the mutant kept for a rerun.
SweepResult sweep(const std::vector<std::pair<std::string, std::string>>& bases,
                  const std::string& command, const std::string& ext, const fs::path& dir) {
  const int count = static_cast<int>(asf_test::envNumber("ASF_MUTATIONS", 40));
  std::mt19937_64 rng(static_cast<unsigned long>(asf_test::envNumber("ASF_MUTATION_SEED", 20)));
  fs::create_directories(dir);
  SweepResult r;
  for (int i = 0; i < count; ++i) {
    const auto& [base_name, base] = bases[static_cast<std::size_t>(i) % bases.size()];
    const fs::path file = dir / ("mutant_" + std::to_string(i) + "_" + base_name + ext);
    {
      std::ofstream out(file, std::ios::binary);
      out << mutate(base, rng);
    }
    // timeout: a hang is a failure; the mutant is run in its own folder (relative paths).
    const auto h =
        asf_test::runHost(command + " '" + file.string() + "'", true, "timeout -s KILL 60 ");
    const std::string name = file.string();
    std::string why;
    if (h.code == 0) {
      ++r.accepted;
    } else if (h.code == 1 || h.code == 2) {
      ++r.rejected;
      if (h.out.find(file.filename().string()) == std::string::npos)
        why = "rejected without naming the file";
      else if (std::regex_search(h.out, std::regex(std::regex_replace(file.filename().string(),
                                                                      std::regex("[.]"), "[.]") +
                                                   ":[0-9]+")))
        ++r.rejected_with_line;
    } else {
      why = h.code == 137 ? "hang (killed after 60 s)"
                          : "crash (exit " + std::to_string(h.code) + ")";
    }
    if (!why.empty()) {
      r.failures.push_back(name + ": " + why + "\n" + h.out.substr(0, 2000));
    } else {
      fs::remove(file);
    }
  }
  std::cout << "[ sweep    ] " << count << " mutants through `asf " << command
            << "`: " << r.accepted << " accepted, " << r.rejected << " rejected naming the file ("
            << r.rejected_with_line << " with file:line), " << r.failures.size() << " failures\n";
  return r;
}

TEST(MutationSweep, DamagedG2oFilesAreOptimizedOrRejectedNamingTheFile) {
  const fs::path dir = fs::temp_directory_path() / "asf_mutation_sweep" / "g2o";
  fs::remove_all(dir);
  const std::vector<std::pair<std::string, std::string>> bases = {{"loop", baseG2o()}};
  const auto r = sweep(bases, "optimize --backend sparse_lm", ".g2o", dir);
  for (const auto& f : r.failures) ADD_FAILURE() << f;
  EXPECT_GT(r.rejected, 0) << "no mutant was rejected: the mutations do not reach the parser";
}

TEST(MutationSweep, DamagedIniFilesAreValidatedOrRejectedNamingTheFile) {
  const fs::path dir = fs::temp_directory_path() / "asf_mutation_sweep" / "ini";
  fs::remove_all(dir);
  std::vector<std::pair<std::string, std::string>> bases;
  for (const auto& e : fs::directory_iterator(fs::path(ASF_TEST_SOURCE_DIR) / "configs")) {
    const std::string text = readText(e.path());
    if (e.path().extension() == ".ini" && text.find("[pipeline]") != std::string::npos)
      bases.emplace_back(e.path().stem().string(), text);
  }
  std::sort(bases.begin(), bases.end());
  ASSERT_GE(bases.size(), 5u);
  const auto r = sweep(bases, "config", ".ini", dir);
  for (const auto& f : r.failures) ADD_FAILURE() << f;
  EXPECT_GT(r.rejected, 0) << "no mutant was rejected: the mutations do not reach the parser";
}

}  // namespace
