#include "process_launcher.h"

#include <asf/errors.h>
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

extern char** environ;

namespace asf::app {

namespace {

/// posix_spawnp of `argv` with stdin from /dev/null and stdout/stderr as `io` says; in a
/// process group of its own with SIGINT and SIGTERM at their defaults (asf installs its own)
/// when `own_group`. Returns the pid, or -1 with `error` saying why.
pid_t spawn(const std::vector<std::string>& argv, const studies::ProcessRunner::Redirect& io,
            bool own_group, std::string& error) {
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  posix_spawn_file_actions_t fa;
  posix_spawnattr_t at;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&fa, 1, io.out.c_str(),
                                   O_WRONLY | O_CREAT | (io.append_out ? O_APPEND : O_TRUNC), 0644);
  if (io.err.empty())
    posix_spawn_file_actions_adddup2(&fa, 1, 2);
  else
    posix_spawn_file_actions_addopen(&fa, 2, io.err.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
  posix_spawnattr_init(&at);
  if (own_group) {
    // A terminal's Ctrl-C reaches only the host, which stops its children itself.
    sigset_t def, none;
    sigemptyset(&def);
    sigaddset(&def, SIGINT);
    sigaddset(&def, SIGTERM);
    sigemptyset(&none);
    posix_spawnattr_setsigdefault(&at, &def);
    posix_spawnattr_setsigmask(&at, &none);
    posix_spawnattr_setpgroup(&at, 0);
    posix_spawnattr_setflags(&at, POSIX_SPAWN_SETPGROUP | POSIX_SPAWN_SETSIGDEF |
                                      POSIX_SPAWN_SETSIGMASK);
  }
  pid_t pid = -1;
  const int rc = posix_spawnp(&pid, args[0], &fa, &at, args.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  posix_spawnattr_destroy(&at);
  if (rc != 0) {
    error = argv[0] + ": cannot start: " + std::strerror(rc);
    return -1;
  }
  return pid;
}

/// Waits for `pid` to end; its exit status or 128 + the signal that ended it.
int waitFor(pid_t pid) {
  int st = 0;
  while (waitpid(pid, &st, 0) < 0)
    if (errno != EINTR) return -1;
  return WIFSIGNALED(st) ? 128 + WTERMSIG(st) : WEXITSTATUS(st);
}

std::atomic<bool>* g_stop = nullptr;
std::atomic<int>* g_signal = nullptr;
extern "C" void onStopSignal(int signo) {
  if (g_signal) *g_signal = signo;
  if (g_stop) *g_stop = true;
}

}  // namespace

std::vector<std::string> ProcessLauncher::resolved(std::vector<std::string> argv) const {
  if (!argv.empty() && argv[0] == "asf") argv[0] = exe_;
  return argv;
}

long ProcessLauncher::start(const std::vector<std::string>& argv, const Redirect& io,
                            std::string& error) {
  if (argv.empty()) {
    error = "no command to start";
    return -1;
  }
  return spawn(resolved(argv), io, true, error);
}

std::optional<studies::ProcessRunner::Exit> ProcessLauncher::poll(long handle) {
  int st = 0;
  const pid_t w = waitpid(static_cast<pid_t>(handle), &st, WNOHANG);
  if (w == 0 || (w < 0 && errno == EINTR)) return std::nullopt;
  Exit e;
  if (w < 0) {
    e.how = Exit::How::Lost;
    e.error = std::string("waitpid: ") + std::strerror(errno);
  } else if (WIFSIGNALED(st)) {
    e.how = Exit::How::Signaled;
    e.code = WTERMSIG(st);
  } else {
    e.code = WEXITSTATUS(st);
  }
  return e;
}

void ProcessLauncher::interrupt(long handle) { ::kill(-static_cast<pid_t>(handle), SIGINT); }

void ProcessLauncher::kill(long handle) { ::kill(-static_cast<pid_t>(handle), SIGKILL); }

int ProcessLauncher::run(const std::vector<std::string>& argv, std::string& output) {
  return runCommand(resolved(argv), output);
}

int runCommand(const std::vector<std::string>& argv, std::string& output) {
  if (argv.empty()) {
    output = "no command to run";
    return -1;
  }
  char path[] = "/tmp/asf-command-XXXXXX";
  const int fd = mkstemp(path);
  if (fd < 0) {
    output = std::string("cannot create a temporary file: ") + std::strerror(errno);
    return -1;
  }
  close(fd);
  std::string error;
  const pid_t pid = spawn(argv, {path, false, ""}, false, error);
  const int code = pid < 0 ? -1 : waitFor(pid);
  if (pid < 0) {
    output = error;
  } else {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    output = text.str();
  }
  unlink(path);
  return code;
}


std::string asfExecutable() {
  std::error_code ec;
  const std::string exe = std::filesystem::read_symlink("/proc/self/exe", ec).string();
  if (ec) throw Error("/proc/self/exe: cannot find the asf binary: " + ec.message());
  return exe;
}

int withStopSignals(std::atomic<bool>& stop, std::atomic<int>& signal,
                    const std::function<int()>& body) {
  stop = false;
  signal = 0;
  g_stop = &stop;
  g_signal = &signal;
  std::signal(SIGINT, onStopSignal);
  std::signal(SIGTERM, onStopSignal);
  struct Restore {
    ~Restore() {
      std::signal(SIGINT, SIG_DFL);
      std::signal(SIGTERM, SIG_DFL);
      g_stop = nullptr;
      g_signal = nullptr;
    }
  } restore;
  return body();
}

}  // namespace asf::app
