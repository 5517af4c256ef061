#pragma once
// The host's one way of starting processes (asf experiment's runs and Slurm commands, asf
// reproduce's stage commands), and of being stopped while they run.
#include <asf/studies/process_runner.h>

#include <atomic>
#include <functional>
#include <string>
#include <vector>

namespace asf::app {

/// ProcessRunner over posix_spawn/waitpid/kill; a handle is the child's pid.
class ProcessLauncher final : public studies::ProcessRunner {
 public:
  /// `asf_exe`: the binary argv[0] == "asf" names (the host's own, asfExecutable()).
  explicit ProcessLauncher(std::string asf_exe) : exe_(std::move(asf_exe)) {}
  long start(const std::vector<std::string>& argv, const Redirect& io,
             std::string& error) override;
  std::optional<Exit> poll(long handle) override;
  void interrupt(long handle) override;
  void kill(long handle) override;
  int run(const std::vector<std::string>& argv, std::string& output) override;

 private:
  /// argv with "asf" as argv[0] replaced by the host's binary.
  std::vector<std::string> resolved(std::vector<std::string> argv) const;
  std::string exe_;
};

/// Runs `argv` (argv[0] looked up in PATH) to its end; ProcessLauncher::run without the
/// host's binary.
int runCommand(const std::vector<std::string>& argv, std::string& output);

/// The asf binary this process runs (/proc/self/exe), which the studies' processes run too.
std::string asfExecutable();

/// Runs `body` with SIGINT and SIGTERM setting `stop` (and `signal` to the signal's number)
/// instead of ending the process, so a study stops its processes and still writes what it
/// has; the default handlers are back after, also on exceptions.
int withStopSignals(std::atomic<bool>& stop, std::atomic<int>& signal,
                    const std::function<int()>& body);

}  // namespace asf::app
