#pragma once
// Helpers shared by the framework tests.
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

namespace asf_test {

/// A file's bytes ("" when it cannot be read).
inline std::string readFile(const std::string& path) {
  std::string out;
  if (FILE* f = std::fopen(path.c_str(), "rb")) {
    std::array<char, 4096> buf;
    std::size_t n;
    while ((n = std::fread(buf.data(), 1, buf.size(), f)) > 0) out.append(buf.data(), n);
    std::fclose(f);
  }
  return out;
}

/// Writes `text` to `path` (binary), creating its folder.
inline void writeFile(const std::filesystem::path& path, const std::string& text) {
  std::filesystem::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << text;
}

/// An empty folder `name` under the system's temporary folder.
inline std::filesystem::path freshTempDir(const std::string& name) {
  const auto d = std::filesystem::temp_directory_path() / name;
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

/// The number in environment variable `name`, or `fallback` when it is unset or empty
/// (sweep sizes and seeds: ASF_MUTATIONS, ASF_KILL_MOMENTS, ...).
inline double envNumber(const char* name, double fallback) {
  const char* v = std::getenv(name);
  return v && *v ? std::atof(v) : fallback;
}

/// The message of the E that fn throws, or a text no expectation matches.
template <class E>
std::string errorOf(const std::function<void()>& fn) {
  try {
    fn();
  } catch (const E& e) {
    return e.what();
  }
  return "(no exception of the expected type thrown)";
}

inline bool has(const std::string& hay, const std::string& needle) {
  return hay.find(needle) != std::string::npos;
}

struct HostResult {
  int code;
  std::string out;  ///< stdout and stderr
};

/// Runs a shell command line and collects its stdout and exit code.
inline HostResult runCommand(const std::string& cmd) {
  FILE* p = popen(cmd.c_str(), "r");
  HostResult r{-1, {}};
  if (!p) return r;
  std::array<char, 4096> buf;
  std::size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), p)) > 0) r.out.append(buf.data(), n);
  const int st = pclose(p);
  r.code = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return r;
}

/// Runs the built host, `asf <args>` (a shell command line), and collects what it printed:
/// stdout and stderr, or stdout only (stderr dropped) with merge_stderr = false. `prefix`
/// goes before the host's path (e.g. "timeout -s KILL 60 ").
inline HostResult runHost(const std::string& args, bool merge_stderr = true,
                          const std::string& prefix = "") {
  return runCommand(prefix + ASF_TEST_BINARY_DIR "/bin/asf " + args +
                    (merge_stderr ? " 2>&1" : " 2>/dev/null"));
}

/// Starts the built host, `asf <args...>`, without waiting for it (to signal it), its stdout
/// and stderr into the file `log`. Returns its pid, -1 when it could not start.
inline pid_t spawnHost(const std::vector<std::string>& args, const std::string& log) {
  std::vector<std::string> all{ASF_TEST_BINARY_DIR "/bin/asf"};
  all.insert(all.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&fa, 1, 2);
  pid_t pid = -1;
  if (posix_spawn(&pid, argv[0], &fa, nullptr, argv.data(), environ) != 0) pid = -1;
  posix_spawn_file_actions_destroy(&fa);
  return pid;
}

}  // namespace asf_test
