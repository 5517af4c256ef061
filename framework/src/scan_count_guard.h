#pragma once
// A stream between MRPT's archive and a rawlog file that refuses a 2D scan whose ray count no
// laser has (and a sensory frame or action collection claiming millions of objects), before
// MRPT allocates for it. MRPT 2.5 reads the count and resizes the scan's
// arrays first: a damaged count of 4294967295 asks for 16.9 GB, and where that allocation
// fails MRPT's aligned allocator returns null and the process dies with SIGSEGV (fuzzing,
// docs/RELIABILITY.md). The guard watches the bytes MRPT reads; when they are the header of a
// CObservation2DRangeScan of a layout it knows (versions 6 to 8, pose as CPose3D 2 or 3)
// it looks ahead to the ray count. Anything else passes unchecked, as before.
#include <mrpt/io/CStream.h>

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace asf {

/// Thrown by ScanCountGuard::Read for a scan claiming more than kMaxScanRays rays. MRPT's
/// deserializer wraps what its stream throws: the reader asks refusal() instead.
struct ScanCountError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class ScanCountGuard : public mrpt::io::CStream {
 public:
  /// More rays than any 2D laser gives (a 360-degree scan at 0.01 degree: 36 000).
  static constexpr std::uint32_t kMaxScanRays = 1u << 20;
  /// More observations (actions) than a sensory frame (action collection) holds.
  static constexpr std::uint32_t kMaxObjects = 1u << 20;

  explicit ScanCountGuard(mrpt::io::CStream& in) : in_(in) {}

  size_t Read(void* buffer, size_t count) override;
  size_t Write(const void*, size_t) override;
  uint64_t Seek(int64_t, mrpt::io::CStream::TSeekOrigin) override;
  uint64_t getTotalBytesCount() const override { return in_.getTotalBytesCount(); }
  /// Bytes handed to the reader so far (the file position minus what was looked ahead).
  uint64_t getPosition() const override { return in_.getPosition() - ahead_.size(); }
  /// Why the last record was refused (empty if it was not).
  const std::string& refusal() const { return refusal_; }

 private:
  size_t readAhead(void* buffer, size_t count);
  /// Makes the look-ahead hold at least n bytes; false at the end of the file.
  bool peek(std::size_t n);
  /// The uint32 at offset i of the look-ahead (peeked before).
  std::uint32_t u32At(std::size_t i) const;
  enum class Header { None, Scan, SensoryFrame, ActionCollection };
  void check(Header h, std::uint8_t version);
  void checkScan(std::uint8_t version);

  mrpt::io::CStream& in_;
  std::vector<std::uint8_t> ahead_;  ///< bytes read from in_ but not handed out yet
  /// The last two reads, for "length byte, class name" and then the version byte.
  std::string last_read_, before_last_;
  Header header_ = Header::None;  ///< the last read was one of these class names
  std::string refusal_;
};

}  // namespace asf
