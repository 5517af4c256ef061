#pragma once
/// \file process_runner.h
/// How a study starts processes: `asf experiment`'s runs and Slurm commands, `asf reproduce`'s
/// stage commands. The host implements it (apps/asf/process_launcher.h, over posix_spawn), so
/// the library never starts a process itself and its tests can script one.
#include <optional>
#include <string>
#include <vector>

namespace asf::studies {

class ProcessRunner {
 public:
  virtual ~ProcessRunner() = default;

  struct Exit {
    enum class How { Exited, Signaled, Lost } how = How::Exited;
    int code = 0;       ///< the exit status, or the signal number when Signaled
    std::string error;  ///< Lost: why
  };
  /// Where a started process writes (its stdin is /dev/null).
  struct Redirect {
    std::string out;          ///< stdout's file, created 0644 and truncated
    bool append_out = false;  ///< append to `out` instead of truncating it
    std::string err;          ///< stderr's file, appended; empty: stdout's
  };

  /// Starts `argv` (argv[0] == "asf": the host's own binary; else a path or a name looked up
  /// in PATH) in a process group of its own (a terminal's Ctrl-C reaches the study only,
  /// which stops its processes itself); returns a handle >= 0, or -1 with `error` saying why.
  virtual long start(const std::vector<std::string>& argv, const Redirect& io,
                     std::string& error) = 0;
  /// Without blocking: how `handle` ended, once it has (the handle is then released).
  virtual std::optional<Exit> poll(long handle) = 0;
  /// Asks the process to stop (SIGINT to its group: asf writes its outputs and exits).
  virtual void interrupt(long handle) = 0;
  /// Ends the process at once (SIGKILL).
  virtual void kill(long handle) = 0;
  /// Runs `argv` (as start() does) to its end, stdout and stderr together in `output`.
  /// Returns the exit status, 128 + the signal that ended it, or -1 with `output` saying
  /// why it could not start.
  virtual int run(const std::vector<std::string>& argv, std::string& output) = 0;
};

/// The exit code of a process that ended as `e` says: its status, 128 + the signal that ended
/// it, -1 when lost.
inline int exitCode(const ProcessRunner::Exit& e) {
  using How = ProcessRunner::Exit::How;
  return e.how == How::Lost ? -1 : e.how == How::Signaled ? 128 + e.code : e.code;
}

}  // namespace asf::studies
