#pragma once
// One run per output folder: asf run holds an advisory lock on DIR/.asf-run.lock for its
// lifetime, so a second run into the same folder stops before writing anything, naming the
// folder and the process that holds it. The kernel drops the lock when the process ends,
// however it ends (kill -9 included): a stale lock file is no obstacle.
#include <string>

namespace asf::framework {

class OutputLock {
 public:
  /// Takes the lock of folder `dir` (which exists); throws asf::Error naming the folder and
  /// the holder's pid when another process has it.
  explicit OutputLock(const std::string& dir);
  ~OutputLock();
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;

 private:
  int fd_ = -1;
};

}  // namespace asf::framework
