#include "checked_output.h"

#include <asf/errors.h>
#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace asf::io {

CheckedFileOutput::CheckedFileOutput(const std::string& file, bool gz, const std::string& name,
                                     bool append)
    : name_(name) {
  if (gz)
    gz_ = gzopen(file.c_str(), append ? "ab1" : "wb1");
  else
    file_ = std::fopen(file.c_str(), append ? "ab" : "wb");
  if (!gz_ && !file_)
    throw InputError(name + ": cannot open for writing: " + std::strerror(errno));
}

CheckedFileOutput::~CheckedFileOutput() {
  if (gz_) gzclose(static_cast<gzFile>(gz_));
  if (file_) std::fclose(file_);
}

size_t CheckedFileOutput::Read(void*, size_t) {
  throw Error(name_ + ": an output stream cannot be read");
}

size_t CheckedFileOutput::Write(const void* buffer, size_t count) {
  if (failed_ || count == 0) return failed_ ? 0 : count;
  size_t done = 0;
  if (gz_) {
    // gzwrite takes an unsigned count: write in pieces below its limit.
    const auto* p = static_cast<const char*>(buffer);
    while (done < count) {
      const unsigned piece = static_cast<unsigned>(std::min<size_t>(count - done, 1u << 30));
      const int n = gzwrite(static_cast<gzFile>(gz_), p + done, piece);
      if (n <= 0) break;
      done += static_cast<size_t>(n);
    }
  } else {
    done = std::fwrite(buffer, 1, count, file_);
  }
  written_ += done;
  if (done < count) failed_ = true;
  return done;
}

uint64_t CheckedFileOutput::Seek(int64_t, mrpt::io::CStream::TSeekOrigin) {
  throw Error(name_ + ": an output stream cannot seek");
}

void CheckedFileOutput::close() {
  bool ok = !failed_;
  if (gz_) {
    ok = gzclose(static_cast<gzFile>(gz_)) == Z_OK && ok;
    gz_ = nullptr;
  }
  if (file_) {
    ok = std::fflush(file_) == 0 && ok;
    ok = std::fclose(file_) == 0 && ok;
    file_ = nullptr;
  }
  if (!ok) throw Error(name_ + ": write failed (disk full or not writable?)");
}

}  // namespace asf::io
