#pragma once
// Helpers of the converter tests (test_convert.cpp, test_carmen.cpp): a temporary folder per
// test, whole files, rawlog frames.
#include <asf/io/rawlog_io.h>
#include <asf/io/text_io.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace asf_test {

/// A fresh folder per test, removed at its end.
class TempDir {
 public:
  TempDir() {
    const auto* t = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = std::filesystem::temp_directory_path() /
            ("asf_test_convert_" + std::string(t->test_suite_name()) + "_" + t->name() + "_" +
             std::to_string(::getpid()));
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  std::string operator/(const std::string& name) const { return (path_ / name).string(); }
  std::string str() const { return path_.string(); }

 private:
  std::filesystem::path path_;
};

inline std::string readText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

inline std::vector<std::string> readLines(const std::string& path) {
  asf::io::LineReader r(path);
  std::vector<std::string> out;
  std::string l;
  while (r.next(l)) out.push_back(l);
  return out;
}

inline void writeText(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

inline std::vector<asf::SensorFrame> readFrames(const std::string& rawlog,
                                                asf::io::RawlogReaderOptions o = {}) {
  asf::io::RawlogReader r(rawlog, std::move(o));
  std::vector<asf::SensorFrame> out;
  while (auto f = r.next()) out.push_back(std::move(*f));
  return out;
}

}  // namespace asf_test
