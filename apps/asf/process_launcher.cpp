#include "process_launcher.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

extern char** environ;

namespace asf::app {

long ProcessLauncher::start(const std::vector<std::string>& args, const std::string& log,
                            std::string& error) {
  std::vector<char*> argv{const_cast<char*>(exe_.c_str())};
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t fa;
  posix_spawnattr_t at;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&fa, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&fa, 1, 2);
  posix_spawnattr_init(&at);
  // Own process group: a terminal's Ctrl-C reaches only the experiment, which forwards one
  // SIGINT to each child. Default SIGINT/SIGTERM dispositions: asf run installs its own.
  sigset_t def, none;
  sigemptyset(&def);
  sigaddset(&def, SIGINT);
  sigaddset(&def, SIGTERM);
  sigemptyset(&none);
  posix_spawnattr_setsigdefault(&at, &def);
  posix_spawnattr_setsigmask(&at, &none);
  posix_spawnattr_setpgroup(&at, 0);
  posix_spawnattr_setflags(&at,
                           POSIX_SPAWN_SETPGROUP | POSIX_SPAWN_SETSIGDEF | POSIX_SPAWN_SETSIGMASK);
  pid_t pid = -1;
  const int rc = posix_spawn(&pid, argv[0], &fa, &at, argv.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  posix_spawnattr_destroy(&at);
  if (rc != 0) {
    error = exe_ + ": cannot start: " + std::strerror(rc);
    return -1;
  }
  return pid;
}

std::optional<RunLauncher::Exit> ProcessLauncher::poll(long handle) {
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

void ProcessLauncher::interrupt(long handle) { ::kill(static_cast<pid_t>(handle), SIGINT); }

void ProcessLauncher::kill(long handle) { ::kill(static_cast<pid_t>(handle), SIGKILL); }

int runCommand(const std::vector<std::string>& args, std::string& output) {
  char path[] = "/tmp/asf-command-XXXXXX";
  const int fd = mkstemp(path);
  if (fd < 0) {
    output = std::string("cannot create a temporary file: ") + std::strerror(errno);
    return -1;
  }
  std::vector<char*> argv;
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_adddup2(&fa, fd, 1);
  posix_spawn_file_actions_adddup2(&fa, fd, 2);
  pid_t pid = -1;
  const int rc = posix_spawnp(&pid, argv[0], &fa, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  close(fd);
  int code = -1;
  if (rc != 0) {
    output = args[0] + ": cannot start: " + std::strerror(rc);
  } else {
    int st = 0;
    while (waitpid(pid, &st, 0) < 0 && errno == EINTR) {
    }
    code = WIFSIGNALED(st) ? 128 + WTERMSIG(st) : WEXITSTATUS(st);
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    output = text.str();
  }
  unlink(path);
  return code;
}

}  // namespace asf::app
