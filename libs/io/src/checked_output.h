#pragma once
// An MRPT output stream over a file that reports every failed write. MRPT's file streams keep
// their buffered writes' and their close's errors to themselves, so a converter writing to a
// full disk or /dev/full would report success; through this stream MRPT's archive throws at
// the first short write and close() throws when the last buffer or the close failed.
#include <mrpt/io/CStream.h>

#include <cstdint>
#include <cstdio>
#include <string>

namespace asf::io {

class CheckedFileOutput final : public mrpt::io::CStream {
 public:
  /// Creates (truncates) `file`, or appends to it; gzip-compressed (level 1, as MRPT writes
  /// rawlogs; appending starts a new gzip member) when `gz`. Throws asf::InputError naming
  /// `name` (the path the user gave) when it cannot.
  CheckedFileOutput(const std::string& file, bool gz, const std::string& name, bool append = false);
  ~CheckedFileOutput() override;  ///< closes, ignoring errors (close() reports them)
  CheckedFileOutput(const CheckedFileOutput&) = delete;
  CheckedFileOutput& operator=(const CheckedFileOutput&) = delete;

  size_t Read(void* buffer, size_t count) override;
  size_t Write(const void* buffer, size_t count) override;  ///< < count: failed
  uint64_t Seek(int64_t offset, mrpt::io::CStream::TSeekOrigin origin) override;
  uint64_t getTotalBytesCount() const override { return written_; }
  uint64_t getPosition() const override { return written_; }

  /// Flushes and closes; throws asf::Error naming the file when anything written was lost.
  void close();

 private:
  std::string name_;
  std::FILE* file_ = nullptr;
  void* gz_ = nullptr;  // gzFile
  std::uint64_t written_ = 0;
  bool failed_ = false;
};

}  // namespace asf::io
