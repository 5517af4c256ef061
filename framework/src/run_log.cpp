#include "run_log.h"

#include <chrono>
#include <ctime>
#include <iomanip>
#include <sstream>

namespace asf::framework {

namespace {

const char* levelName(mrpt::system::VerbosityLevel l) {
  switch (l) {
    case mrpt::system::LVL_DEBUG:
      return "DEBUG";
    case mrpt::system::LVL_INFO:
      return "INFO ";
    case mrpt::system::LVL_WARN:
      return "WARN ";
    case mrpt::system::LVL_ERROR:
      return "ERROR";
    default:
      break;
  }
  return "?    ";
}

}  // namespace

std::string formatLogLine(std::string_view msg, mrpt::system::VerbosityLevel level,
                          std::string_view logger) {
  const auto now = std::chrono::system_clock::now();
  const std::time_t t = std::chrono::system_clock::to_time_t(now);
  const auto ms =
      std::chrono::duration_cast<std::chrono::milliseconds>(now.time_since_epoch()).count() % 1000;
  std::tm tm{};
  localtime_r(&t, &tm);
  std::ostringstream os;
  os << "[" << std::put_time(&tm, "%H:%M:%S") << "." << std::setw(3) << std::setfill('0') << ms
     << "|" << levelName(level) << "|" << logger << "] " << msg;
  std::string s = os.str();
  while (!s.empty() && (s.back() == '\n' || s.back() == '\r')) s.pop_back();
  return s;
}

RunLog::RunLog(const std::string& file, mrpt::system::VerbosityLevel console_level,
               std::FILE* console, bool tty)
    : console_level_(console_level), console_(console), tty_(tty) {
  if (!file.empty()) file_.open(file, std::ios::trunc);
}

RunLog::~RunLog() { endProgress(); }

void RunLog::attach(const std::shared_ptr<RunLog>& self, mrpt::system::COutputLogger& logger) {
  logger.logging_enable_console_output = false;
  logger.logRegisterCallback(
      [self](std::string_view msg, mrpt::system::VerbosityLevel level, std::string_view name,
             const mrpt::Clock::time_point&) { self->write(msg, level, name); });
}

void RunLog::write(std::string_view msg, mrpt::system::VerbosityLevel level,
                   std::string_view logger) {
  const std::string line = formatLogLine(msg, level, logger);
  std::lock_guard<std::mutex> lock(mu_);
  if (file_.is_open()) file_ << line << "\n" << std::flush;
  if (level < console_level_ || !console_) return;
  if (progress_open_) {  // the warning on its own line; the progress comes back at its next turn
    std::fputs("\r\033[K", console_);
    progress_open_ = false;
  }
  std::fputs(line.c_str(), console_);
  std::fputc('\n', console_);
  std::fflush(console_);
}

void RunLog::progress(const std::string& line) {
  std::lock_guard<std::mutex> lock(mu_);
  if (!console_ || console_level_ <= mrpt::system::LVL_INFO) return;
  if (tty_) {
    std::fputs("\r\033[K", console_);
    std::fputs(line.c_str(), console_);
    progress_open_ = true;
  } else {
    std::fputs(line.c_str(), console_);
    std::fputc('\n', console_);
  }
  std::fflush(console_);
}

void RunLog::endProgress() {
  std::lock_guard<std::mutex> lock(mu_);
  if (!progress_open_ || !console_) return;
  std::fputc('\n', console_);
  std::fflush(console_);
  progress_open_ = false;
}

}  // namespace asf::framework
