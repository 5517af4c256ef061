#include <asf/atomic_file.h>
#include <asf/errors.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

namespace asf {

namespace fs = std::filesystem;

AtomicOutput::AtomicOutput(const std::string& path, const std::string& what)
    : path_(path), what_(what), target_(path) {
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);  // follows symbolic links
  if (fs::is_directory(st))
    throw Error(path + ": is a directory, cannot write the " + what + " there");
  if (fs::exists(st) && !fs::is_regular_file(st)) {
    // A device or a pipe: renaming a regular file over it would replace it.
    in_place_ = true;
    file_ = path;
    return;
  }
  // Through a symbolic link: replace the file it points to, keep the link.
  if (fs::is_symlink(fs::symlink_status(path, ec))) {
    const fs::path resolved = fs::weakly_canonical(path, ec);
    if (!ec) target_ = resolved.string();
  }
  file_ = target_ + ".tmp";
}

AtomicOutput::~AtomicOutput() {
  if (!in_place_ && !committed_) std::remove(file_.c_str());
}

void AtomicOutput::commit() {
  if (in_place_ || committed_) return;
  std::error_code ec;
  fs::rename(file_, target_, ec);
  if (ec) throw Error(path_ + ": cannot write the " + what_ + ": " + ec.message());
  committed_ = true;
}

void writeFileVia(const std::string& path, const std::string& what,
                  const std::function<bool(const std::string& file)>& write) {
  AtomicOutput out(path, what);
  if (!write(out.file()))
    throw Error(path + ": cannot write the " + what +
                (out.inPlace() ? "" : " (disk full or not writable?)"));
  out.commit();  // an exception from `write` passes through; out removes the temporary
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

void closeEach(const std::vector<std::pair<std::string, std::function<void()>>>& closers) {
  std::string lost;
  for (const auto& [label, close] : closers) try {
      close();
    } catch (const std::exception& e) {
      if (lost.empty()) lost = label + e.what();
    }
  if (!lost.empty()) throw Error(lost);
}

}  // namespace asf
