#pragma once
/// \file atomic_file.h
/// Writing an output file so that nobody ever reads half of it: into a temporary file beside
/// it, then renamed over it. What `-o FILE` and every run output go through.
#include <functional>
#include <string>

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

/// writeFileVia with `text` as the whole content (binary; the stream's close checked).
void writeFileAtomically(const std::string& path, const std::string& text,
                         const std::string& what = "file");

}  // namespace asf
