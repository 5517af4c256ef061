#pragma once
// Where a run's log lines go (private to the framework). Every line at the run's verbosity
// goes to <out>/run.log; the console gets the lines at or above its own level (warnings and
// errors unless `-v` asked for more) and the progress line: rewritten in place on a terminal,
// one line per progress interval otherwise. Per-event lines (loop closures) stay in the file.
#include <mrpt/system/COutputLogger.h>

#include <cstdio>
#include <fstream>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>

namespace asf::framework {

class RunLog {
 public:
  /// `file` empty: no log file. `console` is written to, a terminal or not as `tty` says.
  RunLog(const std::string& file, mrpt::system::VerbosityLevel console_level, std::FILE* console,
         bool tty);
  ~RunLog();
  RunLog(const RunLog&) = delete;
  RunLog& operator=(const RunLog&) = delete;

  /// Routes `logger`'s lines here (its own console output off). `self` must own this RunLog:
  /// the logger's callback keeps it alive.
  static void attach(const std::shared_ptr<RunLog>& self, mrpt::system::COutputLogger& logger);
  /// One log line (what attached loggers send).
  void write(std::string_view msg, mrpt::system::VerbosityLevel level, std::string_view logger);
  /// The progress line on the console (not when the console shows INFO lines: the progress is
  /// one of them there).
  void progress(const std::string& line);
  /// Ends an in-place progress line (a newline), so what follows starts on its own line.
  void endProgress();
  mrpt::system::VerbosityLevel consoleLevel() const { return console_level_; }

 private:
  std::mutex mu_;
  std::ofstream file_;
  mrpt::system::VerbosityLevel console_level_;
  std::FILE* console_;
  bool tty_;
  bool progress_open_ = false;  ///< a progress line without its newline is on the terminal
};

/// "[hh:mm:ss.mmm|LEVEL|logger] msg" (the console format of MRPT's loggers).
std::string formatLogLine(std::string_view msg, mrpt::system::VerbosityLevel level,
                          std::string_view logger);

}  // namespace asf::framework
