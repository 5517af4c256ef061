#pragma once
// A stream between MRPT's archive and a rawlog file that refuses, before MRPT acts on it, a
// record MRPT 2.5 would crash on (fuzzing, docs/RELIABILITY.md):
// - a 2D scan whose ray count no laser has, and a sensory frame or action collection claiming
//   millions of objects: MRPT resizes its arrays to the count first, and where 16.9 GB cannot
//   be had its aligned allocator returns null and the process dies with SIGSEGV (a deque of
//   1.8 billion actions took 24 GB before the kernel killed it);
// - an odometry action whose motion model claims more than 2^20 particles (MRPT draws them
//   when it reads the action: 996 million took 24 GB);
// - a 3D odometry action whose velocity vectors claim more than 1024 elements;
// - a 3D range scan (versions 9 and 10) whose points or range image claim more than 2^24
//   elements (a 0x7fffffff-row image: SIGSEGV in rangeImage_setSize); its intensity and
//   confidence images and the extra layers of version 10 are not checked;
// - a scan or odometry reading whose sensor label claims more than 64 KB (MRPT fills a string
//   of the length read, up to 4 GB, before finding the bytes missing);
// - an action collection holding something that is not an action (or a null object), and an
//   odometry action whose pose change is not a pose PDF: MRPT casts what it read to the
//   expected class and clones the null result.
// The guard watches the reads MRPT makes: an object header is a one-byte read 0x80 | n, an
// n-byte read naming a registered class (or "nullptr"; MRPT reads the name up to its first
// NUL and resolves it by the part after the last "::", and so does the guard) and a one-byte
// version; an object ends
// with a one-byte read of 0x88. From a collection or an odometry action on it keeps the stack
// of open objects, so it knows what sits directly inside what. A collection whose objects do
// not close after the count it gave is refused too (the bytes do not parse as it claims).
// Everything else passes unchecked, as before.
#include <mrpt/io/CStream.h>

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace asf::io {

/// Thrown by RawlogGuard::Read for a record it refuses. MRPT's deserializer wraps what its
/// stream throws: the reader asks refusal() instead.
struct RawlogRefusal : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class RawlogGuard : public mrpt::io::CStream {
 public:
  /// More rays than any 2D laser gives (a 360-degree scan at 0.01 degree: 36 000).
  static constexpr std::uint32_t kMaxScanRays = 1u << 20;
  /// More observations (actions) than a sensory frame (action collection) holds.
  static constexpr std::uint32_t kMaxObjects = 1u << 20;
  /// Longer than any sensor label.
  static constexpr std::uint32_t kMaxLabel = 1u << 16;
  /// More particles than a motion model draws (MRPT's default: 300).
  static constexpr std::uint32_t kMaxParticles = 1u << 20;
  /// More elements than a small vector of an action holds (velocities: 6).
  static constexpr std::uint32_t kMaxVector = 1u << 10;
  /// More points (pixels) than a 3D camera or lidar gives (4096 x 4096).
  static constexpr std::uint64_t kMaxPixels = std::uint64_t{1} << 24;

  explicit RawlogGuard(mrpt::io::CStream& in) : in_(in) {}

  size_t Read(void* buffer, size_t count) override;
  size_t Write(const void*, size_t) override;
  uint64_t Seek(int64_t, mrpt::io::CStream::TSeekOrigin) override;
  uint64_t getTotalBytesCount() const override { return in_.getTotalBytesCount(); }
  /// Bytes handed to the reader so far (the file position minus what was looked ahead).
  uint64_t getPosition() const override { return in_.getPosition() - ahead_.size(); }
  /// Why the last record was refused (empty if it was not).
  const std::string& refusal() const { return refusal_; }

 private:
  enum class Kind {
    None,
    Scan,
    Scan3D,
    Odometry,
    SensoryFrame,
    ActionCollection,
    Movement2D,
    Movement3D,
    Other
  };
  /// An object open inside a watched one (the outermost is a collection or an odometry action).
  struct Open {
    Kind kind;
    std::uint32_t children = 0;           ///< object headers read directly inside it
    std::uint32_t expected = UINT32_MAX;  ///< a collection's count (max: not known)
    bool pdf_first = false;  ///< an odometry action whose first object must be a pose PDF
  };

  size_t readAhead(void* buffer, size_t count);
  /// Makes the look-ahead hold at least n bytes; false at the end of the file.
  bool peek(std::size_t n);
  /// The uint32 at offset i of the look-ahead (peeked before).
  std::uint32_t u32At(std::size_t i) const;
  void onHeader(const std::string& name);
  void onVersion(Kind kind, std::uint8_t version);
  void onEndFlag();
  void checkCount(Kind kind, std::uint8_t version);
  void checkScan(std::uint8_t version);
  void checkScan3D(std::uint8_t version);
  void checkOdometry(std::uint8_t version);
  void checkMovement2D(std::uint8_t version);
  void checkMovement3D(std::uint8_t version);
  std::size_t nestedHeaderEnd(std::size_t at, const char* cls, std::uint8_t version);
  std::size_t nestedPose2DEnd(std::size_t at);
  std::size_t nestedPose3DEnd(std::size_t at);
  /// Refuses a sensor label (uint32 length at look-ahead offset `at`) over kMaxLabel bytes.
  void checkLabel(std::size_t at, const char* whose);
  [[noreturn]] void refuse(std::string why);

  mrpt::io::CStream& in_;
  std::vector<std::uint8_t> ahead_;  ///< bytes read from in_ but not handed out yet
  /// The last two reads, for "length byte, class name" and then the version byte.
  std::string last_read_, before_last_;
  Kind header_ = Kind::None;  ///< the last read named a class of this kind: a version follows
  std::vector<Open> open_;    ///< objects open in a watched one, outermost first
  std::string refusal_;
};

}  // namespace asf::io
