#pragma once
// The host's way of starting an experiment's runs: the asf binary as child processes.
#include <asf/experiment.h>

#include <string>

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

}  // namespace asf::app
