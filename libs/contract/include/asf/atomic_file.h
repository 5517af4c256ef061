#pragma once
/// \file atomic_file.h
/// Writing an output file so that nobody ever reads half of it: into a temporary file beside
/// it, then renamed over it. What `-o FILE` and every run output go through.
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace asf {

/// Writes the file at `path` with `write(file)`, which writes to the file it is given and
/// returns false when it failed:
/// - a regular file (or none yet): `write` gets PATH.tmp, renamed over PATH when it
///   succeeded; a symbolic link stays a link: the file it points to is replaced;
/// - a character device, FIFO or socket (`-o /dev/stdout`, `-o /dev/null`, a pipe): written
///   in place, never replaced by a regular file;
/// - a directory: an error.
/// On any failure (also a full disk) the temporary file is removed and asf::Error names
/// `path` and `what` ("graph", "plot", ...); an exception from `write` passes through after
/// the clean-up.
void writeFileVia(const std::string& path, const std::string& what,
                  const std::function<bool(const std::string& file)>& write);

/// writeFileVia's rules for a writer that streams its output over a while (a converter):
/// file() is where to write (PATH.tmp beside the file, or the device itself), commit() puts it
/// in place. Destroyed without commit() (an error, an exception), the temporary file is
/// removed and whatever PATH held before is left as it was.
class AtomicOutput {
 public:
  /// Throws asf::Error when `path` is a directory (`what` names the output: "rawlog", ...).
  AtomicOutput(const std::string& path, const std::string& what);
  ~AtomicOutput();
  AtomicOutput(const AtomicOutput&) = delete;
  AtomicOutput& operator=(const AtomicOutput&) = delete;

  const std::string& file() const { return file_; }
  const std::string& path() const { return path_; }
  /// True for a device, FIFO or socket: written in place, nothing to rename.
  bool inPlace() const { return in_place_; }
  /// Renames the temporary file over the target; throws asf::Error naming the path.
  void commit();

 private:
  std::string path_, what_, target_, file_;
  bool in_place_ = false, committed_ = false;
};

/// writeFileVia with `text` as the whole content (binary; the stream's close checked).
void writeFileAtomically(const std::string& path, const std::string& text,
                         const std::string& what = "file");

/// Runs every closer, each even when one before failed, then throws asf::Error with the first
/// failure's message after its label: closing a run's recordings, none is left open by
/// another's loss.
void closeEach(const std::vector<std::pair<std::string, std::function<void()>>>& closers);

}  // namespace asf
