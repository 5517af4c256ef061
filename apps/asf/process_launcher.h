#pragma once
// The host's way of starting an experiment's runs: the asf binary as child processes.
#include <asf/experiment.h>

#include <string>
#include <vector>

namespace asf::app {

/// RunLauncher over posix_spawn/waitpid/kill; a handle is the child's pid.
class ProcessLauncher final : public RunLauncher {
 public:
  /// `asf_exe`: the asf binary the runs execute (the host's own, /proc/self/exe).
  explicit ProcessLauncher(std::string asf_exe) : exe_(std::move(asf_exe)) {}
  long start(const std::vector<std::string>& args, const std::string& log,
             std::string& error) override;
  std::optional<Exit> poll(long handle) override;
  void interrupt(long handle) override;
  void kill(long handle) override;

 private:
  std::string exe_;
};

/// Runs `argv` (argv[0] looked up in PATH) to its end with stdin from /dev/null; its stdout
/// and stderr together in `output`. Returns the exit status, 128 + the signal that ended
/// it, or -1 with `output` saying why it could not start.
int runCommand(const std::vector<std::string>& argv, std::string& output);

}  // namespace asf::app
