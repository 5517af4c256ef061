#include <asf/atomic_file.h>
#include <asf/errors.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

namespace asf {

namespace fs = std::filesystem;

void writeFileVia(const std::string& path, const std::string& what,
                  const std::function<bool(const std::string& file)>& write) {
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);  // follows symbolic links
  if (fs::is_directory(st))
    throw Error(path + ": is a directory, cannot write the " + what + " there");
  if (fs::exists(st) && !fs::is_regular_file(st)) {
    // A device or a pipe: renaming a regular file over it would replace it.
    if (!write(path)) throw Error(path + ": cannot write the " + what);
    return;
  }
  // Through a symbolic link: replace the file it points to, keep the link.
  std::string target = path;
  if (fs::is_symlink(fs::symlink_status(path, ec))) {
    const fs::path resolved = fs::weakly_canonical(path, ec);
    if (!ec) target = resolved.string();
  }
  const std::string tmp = target + ".tmp";
  bool ok = false;
  try {
    ok = write(tmp);
  } catch (...) {
    std::remove(tmp.c_str());
    throw;
  }
  if (!ok) {
    std::remove(tmp.c_str());
    throw Error(path + ": cannot write the " + what + " (disk full or not writable?)");
  }
  fs::rename(tmp, target, ec);
  if (ec) {
    std::remove(tmp.c_str());
    throw Error(path + ": cannot write the " + what + ": " + ec.message());
  }
}

void writeFileAtomically(const std::string& path, const std::string& text,
                         const std::string& what) {
  writeFileVia(path, what, [&](const std::string& file) {
    std::ofstream out(file, std::ios::binary);
    out << text;
    out.close();  // flushes; a full disk shows here
    return !out.fail();
  });
}

}  // namespace asf
